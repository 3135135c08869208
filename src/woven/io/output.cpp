#include "woven/io/output.hpp"

#include <array>
#include <bit>
#include <cstdint>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <cmath>
#include <cstdarg>
#include <filesystem>
#include <fstream>
#include <vector>

#include <Eigen/Geometry>

#include <unistd.h>

#include "woven/common/error.hpp"
#include "woven/common/format.hpp"
#include "woven/geometry/mesh_ops.hpp"
#include "woven/io/output_set.hpp"

namespace woven::io {

namespace {

void check_grid(const Positions& x, int nu, int nv, const char* what)
{
    if (nu < 2 || nv < 2 || static_cast<long long>(nu) * nv != static_cast<long long>(x.size()))
        throw InputError(what, "grid",
                         strf("%zu positions do not form a %d x %d grid (need nu, nv >= 2)", x.size(), nu, nv));
}

}  // namespace

void write_file_atomic(const std::string& path, std::string_view contents)
{
    // A unique temporary name in the same folder (io::OutputSet's pattern, so that one left by a
    // killed process is removed by the next run writing there).
    static std::atomic<long> counter{0};
    const std::filesystem::path p(path);
    const std::string tmp = (p.parent_path() / (std::string(kTempPrefix) + std::to_string(::getpid()) + ".a" +
                                                std::to_string(counter++) + "." + p.filename().string()))
                                .string();
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) throw RuntimeError(strf("%s: cannot write: %s", path.c_str(), std::strerror(errno)));
        out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
        out.close();
        if (!out) {
            std::remove(tmp.c_str());
            throw RuntimeError(strf("%s: write failed: %s", path.c_str(), std::strerror(errno)));
        }
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        const int e = errno;
        std::remove(tmp.c_str());
        throw RuntimeError(strf("%s: cannot rename %s into place: %s", path.c_str(), tmp.c_str(), std::strerror(e)));
    }
}

std::string cloth_obj(const Positions& x, int nu, int nv)
{
    check_grid(x, nu, nv, "cloth OBJ");
    const geometry::TriangleMesh mesh = geometry::grid_mesh(x, nu, nv);
    const Positions n = geometry::vertex_normals(mesh);
    std::string s;
    s.reserve(x.size() * 120);
    s += "# woven cloth, units: m\n";
    s += strf("# grid %d x %d particles (nu x nv), vertex index = i + nu * j + 1\n", nu, nv);
    s += "# vt: u = i/(nu-1) along the weft, v = j/(nv-1) along the warp\n";
    s += "o cloth\n";
    for (const auto& p : x) s += strf("v %.9g %.9g %.9g\n", p.x(), p.y(), p.z());
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i)
            s += strf("vt %.9g %.9g\n", double(i) / (nu - 1), double(j) / (nv - 1));
    for (const auto& v : n) s += strf("vn %.6f %.6f %.6f\n", v.x(), v.y(), v.z());
    for (const auto& t : mesh.faces) {
        const int a = t[0] + 1, b = t[1] + 1, c = t[2] + 1;
        s += strf("f %d/%d/%d %d/%d/%d %d/%d/%d\n", a, a, a, b, b, b, c, c, c);
    }
    return s;
}

std::string cloth_ply(const Positions& x, int nu, int nv, const std::vector<analysis::VertexField>& fields, PlyFormat format)
{
    check_grid(x, nu, nv, "cloth PLY");
    for (const auto& f : fields)
        if (f.values.size() != x.size())
            throw InputError("cloth PLY", f.name, strf("%zu values for %zu particles", f.values.size(), x.size()));
    const bool binary = format == PlyFormat::BINARY;
    const geometry::TriangleMesh mesh = geometry::grid_mesh(x, nu, nv);
    const Positions n = geometry::vertex_normals(mesh);
    const auto& tris = mesh.faces;
    std::string s;
    s.reserve(x.size() * (binary ? 40 + 4 * fields.size() : 120 + 16 * fields.size()));
    s += binary ? "ply\nformat binary_little_endian 1.0\n" : "ply\nformat ascii 1.0\n";
    s += "comment woven cloth, units: m\n";
    s += strf("comment grid %d x %d particles (nu x nv), vertex index = i + nu * j\n", nu, nv);
    s += "comment u = i/(nu-1) along the weft, v = j/(nv-1) along the warp\n";
    for (const auto& f : fields) s += "comment " + f.name + " unit: " + f.unit + "\n";
    s += strf("element vertex %zu\n", x.size());
    for (const char* p : {"x", "y", "z"}) s += strf("property double %s\n", p);
    for (const char* p : {"nx", "ny", "nz", "u", "v"}) s += strf("property float %s\n", p);
    for (const auto& f : fields) s += "property float " + f.name + "\n";
    s += strf("element face %zu\n", tris.size());
    s += "property list uchar int vertex_indices\nend_header\n";
    // Binary: little-endian (x86-64's own order) values appended as their bytes.
    static_assert(std::endian::native == std::endian::little, "the binary PLY writer assumes a little-endian machine");
    auto put = [&s](auto value) { s.append(reinterpret_cast<const char*>(&value), sizeof value); };
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            const int k = i + nu * j;
            const double u = double(i) / (nu - 1), v = double(j) / (nv - 1);
            if (binary) {
                for (int c = 0; c < 3; ++c) put(x[k][c]);
                for (int c = 0; c < 3; ++c) put(static_cast<float>(n[k][c]));
                put(static_cast<float>(u));
                put(static_cast<float>(v));
                for (const auto& f : fields) put(static_cast<float>(f.values[k]));
            } else {
                s += strf("%.9g %.9g %.9g %.6f %.6f %.6f %.9g %.9g", x[k].x(), x[k].y(), x[k].z(), n[k].x(), n[k].y(),
                          n[k].z(), u, v);
                for (const auto& f : fields) s += strf(" %.7g", f.values[k]);
                s += "\n";
            }
        }
    for (const auto& t : tris) {
        if (binary) {
            put(static_cast<unsigned char>(3));
            for (int c = 0; c < 3; ++c) put(static_cast<std::int32_t>(t[c]));
        } else {
            s += strf("3 %d %d %d\n", t[0], t[1], t[2]);
        }
    }
    return s;
}

}  // namespace woven::io
