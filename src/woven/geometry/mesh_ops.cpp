#include "woven/geometry/mesh_ops.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <unordered_map>

#include <Eigen/Geometry>

#include "woven/common/error.hpp"

namespace woven::geometry {

TriangleMesh grid_mesh(const Positions& x, int nu, int nv)
{
    if (nu < 2 || nv < 2 || x.size() != static_cast<std::size_t>(nu) * nv)
        throw InputError("cloth grid", std::to_string(x.size()) + " positions",
                         "expected nu * nv = " + std::to_string(static_cast<long long>(nu) * nv) + " with nu, nv >= 2 (nu " +
                             std::to_string(nu) + ", nv " + std::to_string(nv) + ")");
    TriangleMesh m;
    m.vertices.assign(x.begin(), x.end());
    m.faces.reserve(2 * static_cast<std::size_t>(nu - 1) * (nv - 1));
    for (int j = 0; j + 1 < nv; ++j)
        for (int i = 0; i + 1 < nu; ++i) {
            const int a = i + nu * j, b = a + 1, c = a + 1 + nu, d = a + nu;
            m.faces.emplace_back(a, b, c);
            m.faces.emplace_back(a, c, d);
        }
    return m;
}

Positions vertex_normals(const TriangleMesh& mesh)
{
    Positions n(mesh.vertices.size(), Vec3::Zero());
    for (const auto& f : mesh.faces) {
        // The cross product's length is twice the area: area weighting for free.
        const Vec3 fn = (mesh.vertices[f[1]] - mesh.vertices[f[0]]).cross(mesh.vertices[f[2]] - mesh.vertices[f[0]]);
        for (int k = 0; k < 3; ++k) n[f[k]] += fn;
    }
    for (auto& v : n) {
        const double len = v.norm();
        v = (len > 0 && std::isfinite(len)) ? Vec3(v / len) : Vec3(0, 0, 1);
    }
    return n;
}

TriangleMesh transform(const TriangleMesh& mesh, double scale, const Vec3& rotation_deg, const Vec3& translate)
{
    const Vec3 r = rotation_deg * (std::numbers::pi / 180.0);
    const Mat3 R = (Eigen::AngleAxisd(r.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(r.y(), Vec3::UnitY()) *
                    Eigen::AngleAxisd(r.x(), Vec3::UnitX()))
                       .toRotationMatrix();
    TriangleMesh out;
    out.faces = mesh.faces;
    out.vertices.reserve(mesh.vertices.size());
    for (const Vec3& v : mesh.vertices) out.vertices.push_back(R * (scale * v) + translate);
    return out;
}

bool is_closed(const TriangleMesh& mesh)
{
    if (mesh.faces.empty()) return false;
    const auto n = static_cast<std::int64_t>(mesh.vertices.size());
    // Directed edge (a, b) -> count. Closed and consistent: each directed edge once, and its
    // reverse once.
    std::unordered_map<std::uint64_t, int> directed;
    directed.reserve(mesh.faces.size() * 3);
    auto key = [](std::int64_t a, std::int64_t b) { return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint64_t>(b); };
    for (const auto& f : mesh.faces) {
        for (int k = 0; k < 3; ++k) {
            const std::int64_t a = f[k], b = f[(k + 1) % 3];
            if (a < 0 || b < 0 || a >= n || b >= n || a == b) return false;
            if (++directed[key(a, b)] > 1) return false;
        }
    }
    for (const auto& [k, count] : directed) {
        const std::uint64_t a = k >> 32, b = k & 0xffffffffu;
        if (!directed.count((b << 32) | a)) return false;
    }
    return true;
}

double signed_volume(const TriangleMesh& mesh)
{
    double v = 0;
    for (const auto& f : mesh.faces) {
        v += mesh.vertices[f[0]].dot(mesh.vertices[f[1]].cross(mesh.vertices[f[2]]));
    }
    return v / 6.0;
}

}  // namespace woven::geometry
