#include "woven/io/mesh_file.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "woven/common/error.hpp"
#include "woven/io/input_file.hpp"
#include "woven/io/toml_reader.hpp"

namespace woven::io {

namespace {

/// Tokens of one line, split at blanks.
std::vector<std::string_view> tokens(std::string_view line)
{
    std::vector<std::string_view> t;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
        const std::size_t b = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
        if (i > b) t.push_back(line.substr(b, i - b));
    }
    return t;
}

std::string shown(std::string_view s)
{
    std::string t = "'";  // appended: "'" + std::string made GCC 12 warn falsely (-Wrestrict)
    t += printable(s, 40);
    t += '\'';
    return t;
}

}  // namespace

geometry::TriangleMesh parse_obj_mesh(std::string_view text, const std::string& source)
{
    if (text.size() > kMaxObjBytes)
        throw InputError(source, "file",
                         "expected an OBJ file of at most " + std::to_string(kMaxObjBytes >> 20) + " MiB, got " +
                             std::to_string(text.size()) + " bytes");
    geometry::TriangleMesh mesh;
    struct Corner {
        long long index;  ///< 0-based, or >= vertex count: checked at the end
        long long line;
    };
    std::vector<std::array<Corner, 3>> faces;
    long long line_no = 0;
    std::size_t pos = 0;
    while (pos < text.size()) {
        std::size_t end = text.find('\n', pos);
        if (end == std::string_view::npos) end = text.size();
        std::string_view line = text.substr(pos, end - pos);
        pos = end + 1;
        ++line_no;
        if (const auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
        const auto t = tokens(line);
        if (t.empty()) continue;
        auto fail = [&](const std::string& field, const std::string& expected) -> void {
            throw InputError(source + ":" + std::to_string(line_no), field, expected);
        };
        if (t[0] == "v") {
            // x y z, and an optional weight w that is ignored (as are vertex colours after it).
            if (t.size() < 4) fail("v", "expected 3 coordinates, got " + std::to_string(t.size() - 1));
            Vec3 p;
            for (int c = 0; c < 3; ++c) {
                const std::string_view s = t[1 + c];
                // from_chars takes no '+': "+0.2" (as some writers print) is read without it.
                const std::string_view digits = s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+' ? s.substr(1) : s;
                double v = 0;
                const auto r = std::from_chars(digits.data(), digits.data() + digits.size(), v);
                if (r.ec != std::errc() || r.ptr != digits.data() + digits.size() || !std::isfinite(v) ||
                    std::abs(v) > kMaxObjCoordinate)
                    fail("v", "expected a number in [-" + std::to_string(static_cast<long long>(kMaxObjCoordinate)) +
                                  ", " + std::to_string(static_cast<long long>(kMaxObjCoordinate)) + "], got " +
                                  shown(s));
                p[c] = v;
            }
            if (static_cast<long long>(mesh.vertices.size()) >= kMaxObjVertices)
                fail("v", "expected at most " + std::to_string(kMaxObjVertices) + " vertices");
            mesh.vertices.push_back(p);
        } else if (t[0] == "f") {
            if (t.size() < 4) fail("f", "expected at least 3 vertices, got " + std::to_string(t.size() - 1));
            std::vector<Corner> corners;
            for (std::size_t k = 1; k < t.size(); ++k) {
                const std::string_view s = t[k].substr(0, t[k].find('/'));  // v, v/vt, v//vn, v/vt/vn
                long long v = 0;
                const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
                const long long nv = static_cast<long long>(mesh.vertices.size());
                if (r.ec != std::errc() || r.ptr != s.data() + s.size() || v == 0 || v < -nv || v > kMaxObjVertices)
                    fail("f", "expected a vertex index in [1, " + std::to_string(kMaxObjVertices) + "] or in [-" +
                                  std::to_string(nv) + ", -1] (relative), got " + shown(t[k]));
                corners.push_back({v > 0 ? v - 1 : nv + v, line_no});
            }
            if (faces.size() + corners.size() > static_cast<std::size_t>(kMaxObjVertices) * 2)
                fail("f", "expected at most " + std::to_string(2 * kMaxObjVertices) + " triangles");
            for (std::size_t k = 1; k + 1 < corners.size(); ++k) faces.push_back({corners[0], corners[k], corners[k + 1]});
        }
        // Other statements (vt, vn, o, g, s, usemtl, mtllib, l, p, ...) are ignored.
    }
    const long long nv = static_cast<long long>(mesh.vertices.size());
    for (const auto& f : faces) {
        Eigen::Vector3i face;
        for (int c = 0; c < 3; ++c) {
            if (f[c].index >= nv)
                throw InputError(source + ":" + std::to_string(f[c].line), "f",
                                 "vertex index " + std::to_string(f[c].index + 1) + " out of range (the file has " +
                                     std::to_string(nv) + " vertices)");
            face[c] = static_cast<int>(f[c].index);
        }
        if (face[0] == face[1] || face[1] == face[2] || face[0] == face[2]) continue;  // degenerate
        mesh.faces.push_back(face);
    }
    if (mesh.faces.empty()) throw InputError(source, "faces", "the OBJ file has no faces");
    return mesh;
}

geometry::TriangleMesh load_obj_mesh(const std::string& path)
{
    return parse_obj_mesh(read_input_file(path, kMaxObjBytes, {"mesh file", "an OBJ file"}), path);
}

}  // namespace woven::io
