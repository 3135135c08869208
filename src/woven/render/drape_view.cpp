#include "woven/render/drape_view.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "woven/common/error.hpp"

namespace woven::render {

namespace {

constexpr double kSideElevationDeg = 12;    // front and side views
constexpr double kCornerElevationDeg = 20;  // the corner view
const Vec3 kObstacleColor(0.42, 0.42, 0.42);
const Vec3 kFloorColor(0.78, 0.77, 0.75);

/// Catmull-Rom weights at t in [0, 1] for the points p[-1], p[0], p[1], p[2].
std::array<double, 4> catmull_rom(double t)
{
    const double t2 = t * t, t3 = t2 * t;
    return {0.5 * (-t3 + 2 * t2 - t), 0.5 * (3 * t3 - 5 * t2 + 2), 0.5 * (-3 * t3 + 4 * t2 + t), 0.5 * (t3 - t2)};
}

Vec3 direction(double azimuth_deg, double elevation_deg)
{
    const double a = azimuth_deg * std::numbers::pi / 180, e = elevation_deg * std::numbers::pi / 180;
    return Vec3(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
}

}  // namespace

ClothSurface grid_surface(const Positions& x, int nu, int nv, int refine)
{
    if (nu < 2 || nv < 2 || x.size() != static_cast<std::size_t>(nu) * nv)
        throw InputError("render", "cloth", "nu * nv positions with nu, nv >= 2");
    if (refine < 1 || refine > 8) throw InputError("render", "refine", "1 .. 8 subdivisions per cell");
    // Point (i, j) with ghost points outside the grid extended linearly.
    auto at = [&](int i, int j) -> Vec3 {
        const int ci = std::clamp(i, 0, nu - 1), cj = std::clamp(j, 0, nv - 1);
        Vec3 p = x[ci + nu * cj];
        if (i != ci) p += (i - ci) * (x[ci + nu * cj] - x[(ci + (i < 0 ? 1 : -1)) + nu * cj]);
        if (j != cj) p += (j - cj) * (x[ci + nu * cj] - x[ci + nu * (cj + (j < 0 ? 1 : -1))]);
        return p;
    };
    const int mu = (nu - 1) * refine + 1, mv = (nv - 1) * refine + 1;
    ClothSurface s;
    s.mesh.vertices.resize(static_cast<std::size_t>(mu) * mv);
    s.uv.resize(s.mesh.vertices.size());
    for (int b = 0; b < mv; ++b) {
        const int j = std::min(b / refine, nv - 2);
        const auto wj = catmull_rom(static_cast<double>(b - j * refine) / refine);
        for (int a = 0; a < mu; ++a) {
            const int i = std::min(a / refine, nu - 2);
            const auto wi = catmull_rom(static_cast<double>(a - i * refine) / refine);
            Vec3 p = Vec3::Zero();
            for (int l = 0; l < 4; ++l)
                for (int k = 0; k < 4; ++k) p += wi[k] * wj[l] * at(i - 1 + k, j - 1 + l);
            s.mesh.vertices[a + mu * b] = p;
            s.uv[a + mu * b] = Eigen::Vector2d(static_cast<double>(a) / refine, static_cast<double>(b) / refine);
        }
    }
    for (int b = 0; b + 1 < mv; ++b)
        for (int a = 0; a + 1 < mu; ++a) {
            const int p0 = a + mu * b, p1 = p0 + 1, p2 = p0 + 1 + mu, p3 = p0 + mu;
            s.mesh.faces.emplace_back(p0, p1, p2);
            s.mesh.faces.emplace_back(p0, p2, p3);
        }
    double len = 0;
    int count = 0;
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i + 1 < nu; ++i) {
            const double d = (x[i + 1 + nu * j] - x[i + nu * j]).norm();
            if (std::isfinite(d)) {
                len += d;
                ++count;
            }
        }
    s.spacing_m = count ? len / count : 0;
    return s;
}

Vec3 fabric_color(const std::optional<std::array<double, 3>>& srgb)
{
    const std::array<double, 3> c = srgb.value_or(std::array<double, 3>{0.70, 0.28, 0.16});
    Vec3 linear;
    for (int k = 0; k < 3; ++k) linear[k] = std::pow(std::clamp(c[k], 0.0, 1.0), 2.2);  // the renderer's gamma
    return linear;
}

std::optional<View> parse_view(const std::string& name) { return value_named(kViewNames, name); }

std::string view_name(View view)
{
    const char* name = name_of(kViewNames, view);
    return name ? name : "scene";
}

Camera view_camera(const DrapeScene& scene, View view, double aspect, double fov_deg)
{
    std::vector<Vec3> points(scene.cloth.mesh.vertices.begin(), scene.cloth.mesh.vertices.end());
    if (scene.obstacles)
        for (std::size_t k = 0; k < scene.obstacles->size(); ++k) {
            const geometry::Obstacle& o = (*scene.obstacles)[k];
            if (o.kind() == "plane") continue;
            const geometry::TriangleMesh m = o.tessellate();
            points.insert(points.end(), m.vertices.begin(), m.vertices.end());
        }
    Vec3 forward, up = Vec3::UnitZ();
    switch (view) {
    case View::SCENE:
        if (scene.scene_camera && (scene.scene_camera->target - scene.scene_camera->eye).norm() > 0) {
            forward = scene.scene_camera->target - scene.scene_camera->eye;
            break;
        }
        [[fallthrough]];
    case View::CORNER: forward = -direction(-45, kCornerElevationDeg); break;
    case View::FRONT: forward = -direction(-90, kSideElevationDeg); break;
    case View::SIDE: forward = -direction(0, kSideElevationDeg); break;
    case View::TOP:
        forward = -Vec3::UnitZ();
        up = Vec3::UnitY();
        break;
    }
    return fit_camera(points, forward, up, fov_deg, aspect);
}

Image render_drape(const DrapeScene& scene, const Camera& camera, RenderOptions options)
{
    std::vector<RenderMesh> meshes;
    RenderMesh cloth;
    cloth.mesh = scene.cloth.mesh;
    cloth.uv = scene.cloth.uv;
    cloth.color = scene.cloth_color;
    cloth.surface = Surface::CLOTH;
    meshes.push_back(std::move(cloth));
    if (scene.obstacles)
        for (std::size_t k = 0; k < scene.obstacles->size(); ++k) {
            const geometry::Obstacle& o = (*scene.obstacles)[k];
            RenderMesh m;
            m.mesh = o.tessellate();
            const bool floor = o.kind() == "plane";
            m.surface = floor ? Surface::FLOOR : Surface::SOLID;
            m.color = floor ? kFloorColor : kObstacleColor;
            meshes.push_back(std::move(m));
        }
    if (options.cloth_priority_m == 0 && scene.cloth.spacing_m > 0) options.cloth_priority_m = scene.cloth.spacing_m;
    // Key light from above, behind the camera's left shoulder (as a photographer's key).
    const Vec3 f = (camera.target - camera.eye).normalized();
    Vec3 r = f.cross(camera.up);
    r = r.norm() > 1e-9 ? Vec3(r.normalized()) : Vec3::UnitX();
    Vec3 back(-f.x(), -f.y(), 0);
    if (back.norm() < 1e-6) back = -Vec3(camera.up.x(), camera.up.y(), 0);  // looking straight down
    back = back.norm() > 1e-9 ? Vec3(back.normalized()) : Vec3(-Vec3::UnitY());
    options.light_dir = (-0.75 * r + 0.35 * back + 0.95 * Vec3::UnitZ()).normalized();
    return render(meshes, camera, options);
}

}  // namespace woven::render
