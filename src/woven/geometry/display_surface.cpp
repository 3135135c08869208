#include "woven/geometry/display_surface.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace woven::geometry {

namespace {

/// Calls f(point) at the barycentric grid of triangle `f` with `samples` + 1 points per edge.
template <class F>
void for_samples(const TriangleMesh& mesh, const Eigen::Vector3i& face, int samples, F&& f)
{
    const Vec3& a = mesh.vertices[face[0]];
    const Vec3& b = mesh.vertices[face[1]];
    const Vec3& c = mesh.vertices[face[2]];
    for (int i = 0; i <= samples; ++i)
        for (int j = 0; i + j <= samples; ++j) {
            const double u = double(i) / samples, v = double(j) / samples;
            f(Vec3((1 - u - v) * a + u * b + v * c));
        }
}

}  // namespace

LiftedSurface lift_off_obstacles(const TriangleMesh& mesh, const ObstacleSet& obstacles, double clearance, int samples, int rounds)
{
    LiftedSurface out{mesh, 0};
    if (obstacles.empty() || mesh.faces.empty()) return out;
    samples = std::max(samples, 1);
    const std::size_t n = mesh.vertices.size();
    std::vector<Vec3, Eigen::aligned_allocator<Vec3>> push(n);
    std::vector<double> size(n);
    for (int round = 0; round < rounds; ++round) {
        std::fill(push.begin(), push.end(), Vec3::Zero());
        std::fill(size.begin(), size.end(), 0.0);
        bool any = false;
        for (const auto& face : out.mesh.faces) {
            double worst = 0;
            Vec3 where = Vec3::Zero();
            // At least `samples` per edge, and dense enough that an obstacle's edge between two
            // samples cannot reach the surface (samples 2 clearances apart at most).
            const Vec3& a = out.mesh.vertices[face[0]];
            const Vec3& b = out.mesh.vertices[face[1]];
            const Vec3& c = out.mesh.vertices[face[2]];
            const double edge = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
            const int n = std::clamp(static_cast<int>(std::ceil(edge / (2 * clearance))), samples, 48);
            for_samples(out.mesh, face, n, [&](const Vec3& p) {
                const double short_by = clearance - obstacles.distance(p);
                if (short_by > worst) {
                    worst = short_by;
                    where = p;
                }
            });
            if (!(worst > 0)) continue;
            any = true;
            const Vec3 normal = obstacles.closest(where).normal;
            for (int k = 0; k < 3; ++k)
                if (worst > size[face[k]]) {
                    size[face[k]] = worst;
                    push[face[k]] = worst * normal;
                }
        }
        if (!any) break;
        for (std::size_t v = 0; v < n; ++v) {
            if (!(size[v] > 0)) continue;
            Vec3& p = out.mesh.vertices[v];
            // A triangle's push (the normal at its worst sample) may point into the obstacle
            // at this vertex: over a thin disc's rim a sample under the rim pushed the vertices
            // on the disc's top down through it (Cusick at 2 cm: up to 17 mm, holes over the
            // disc). A vertex never moves closer to an obstacle: it takes the same lift along its
            // own outward normal instead.
            const double before = obstacles.distance(p);
            if (obstacles.distance(p + push[v]) < std::min(before, clearance)) {
                const Vec3 own = obstacles.closest(p).normal;
                const Vec3 lifted = p + size[v] * own;
                if (obstacles.distance(lifted) >= std::min(before, clearance)) p = lifted;
                continue;
            }
            p += push[v];
        }
    }
    for (std::size_t v = 0; v < n; ++v) out.max_lift = std::max(out.max_lift, (out.mesh.vertices[v] - mesh.vertices[v]).norm());
    return out;
}

double min_sampled_distance(const TriangleMesh& mesh, const ObstacleSet& obstacles, int samples)
{
    double d = std::numeric_limits<double>::infinity();
    for (const auto& face : mesh.faces) for_samples(mesh, face, std::max(samples, 1), [&](const Vec3& p) { d = std::min(d, obstacles.distance(p)); });
    return d;
}

}  // namespace woven::geometry
