#include "woven/geometry/dress_form.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace woven::geometry {

namespace {

/// (height above the waist, girth) of the profile's keys, from the top down.
std::vector<std::array<double, 2>> profile(const DressFormSizes& s)
{
    return {{0.30, 0.92 * s.bust},
            {0.22, s.bust},
            {0.10, s.waist + 0.4 * (s.bust - s.waist)},
            {0.0, s.waist},
            {-0.10, s.waist + 0.6 * (s.hip - s.waist)},
            {-s.hip_depth, s.hip},
            {-s.hip_depth - 0.12, 0.97 * s.hip},
            {-s.hip_depth - 0.22, 0.90 * s.hip}};
}

}  // namespace

double dress_form_top(const DressFormSizes& s) { return s.waist_height + profile(s).front()[0]; }
double dress_form_bottom(const DressFormSizes& s) { return s.waist_height + profile(s).back()[0]; }

double dress_form_girth(const DressFormSizes& s, double z)
{
    const auto keys = profile(s);
    const double h = z - s.waist_height;
    if (h > keys.front()[0] || h < keys.back()[0]) return 0.0;
    for (std::size_t k = 0; k + 1 < keys.size(); ++k) {
        const double z0 = keys[k][0], z1 = keys[k + 1][0];
        if (h <= z0 && h >= z1) {
            const double t = (z0 - h) / (z0 - z1);
            const double blend = 0.5 - 0.5 * std::cos(std::numbers::pi * t);
            return keys[k][1] + (keys[k + 1][1] - keys[k][1]) * blend;
        }
    }
    return keys.back()[1];
}

void ellipse_axes(double girth, double depth_ratio, double& a, double& b)
{
    const double r = depth_ratio;
    const double h = ((1 - r) / (1 + r)) * ((1 - r) / (1 + r));
    a = girth / (std::numbers::pi * (1 + r) * (1 + 3 * h / (10 + std::sqrt(4 - 3 * h))));
    b = r * a;
}

TriangleMesh dress_form_mesh(const DressFormSizes& s, int around, double step)
{
    TriangleMesh mesh;
    const double top = dress_form_top(s), bottom = dress_form_bottom(s);
    const int levels = std::max(2, static_cast<int>(std::ceil((top - bottom) / step)) + 1);
    for (int l = 0; l < levels; ++l) {  // from the bottom up
        const double z = bottom + (top - bottom) * l / (levels - 1);
        double a = 0, b = 0;
        ellipse_axes(dress_form_girth(s, std::clamp(z, bottom, top)), s.depth_ratio, a, b);
        for (int k = 0; k < around; ++k) {
            const double phi = 2 * std::numbers::pi * k / around;
            mesh.vertices.push_back(Vec3(a * std::cos(phi), b * std::sin(phi), z));
        }
    }
    const int bottom_centre = static_cast<int>(mesh.vertices.size());
    mesh.vertices.push_back(Vec3(0, 0, bottom));
    const int top_centre = bottom_centre + 1;
    mesh.vertices.push_back(Vec3(0, 0, top));
    auto v = [&](int l, int k) { return l * around + (k % around); };
    for (int l = 0; l + 1 < levels; ++l)
        for (int k = 0; k < around; ++k) {
            // counter-clockwise seen from outside: angle increases to the right looking in
            mesh.faces.push_back(Eigen::Vector3i(v(l, k), v(l, k + 1), v(l + 1, k + 1)));
            mesh.faces.push_back(Eigen::Vector3i(v(l, k), v(l + 1, k + 1), v(l + 1, k)));
        }
    for (int k = 0; k < around; ++k) {
        mesh.faces.push_back(Eigen::Vector3i(bottom_centre, v(0, k + 1), v(0, k)));
        mesh.faces.push_back(Eigen::Vector3i(top_centre, v(levels - 1, k), v(levels - 1, k + 1)));
    }
    return mesh;
}

}  // namespace woven::geometry
