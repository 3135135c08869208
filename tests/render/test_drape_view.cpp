// render / drape pictures: cloth pixels where the mesh projects, obstacles never through the
// cloth lying on them, tight framing, the smooth cloth surface, determinism.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "woven/common/error.hpp"
#include "woven/geometry/primitives.hpp"
#include "woven/render/drape_view.hpp"

using namespace woven;
using render::Camera;
using render::Image;
using render::RenderMesh;
using render::RenderOptions;

namespace {

constexpr double kPi = 3.14159265358979323846;

std::array<int, 3> pixel(const Image& img, int x, int y)
{
    const std::uint8_t* p = &img.rgb[(static_cast<std::size_t>(y) * img.width + x) * 3];
    return {p[0], p[1], p[2]};
}

/// A wavy sheet, nu x nv particles over [-0.5, 0.5]^2 (m), hanging in folds.
Positions wavy_grid(int nu, int nv)
{
    Positions x;
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            const double u = -0.5 + static_cast<double>(i) / (nu - 1), v = -0.5 + static_cast<double>(j) / (nv - 1);
            x.emplace_back(u, v, 0.4 + 0.08 * std::sin(9 * u) * std::cos(5 * v));
        }
    return x;
}

/// A coarse UV sphere (slices x stacks) whose vertices lie on the surface of `o` pushed out
/// by `lift` along the ray from `centre`: a closed cloth lying on the obstacle, flat between
/// its vertices, so the obstacle pokes through between them (at edges and on curved parts).
geometry::TriangleMesh wrap(const geometry::Obstacle& o, const Vec3& centre, double lift, int slices, int stacks)
{
    geometry::TriangleMesh m;
    for (int i = 0; i <= stacks; ++i)
        for (int j = 0; j < slices; ++j) {
            const double th = kPi * (i + 0.5 * (i > 0 && i < stacks)) / (stacks + 1), ph = 2 * kPi * (j + 0.37) / slices;
            const Vec3 d(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
            // Bisect the ray for the surface.
            double a = 0, b = 10;
            for (int k = 0; k < 80; ++k) {
                const double mid = 0.5 * (a + b);
                (o.distance(centre + mid * d) < 0 ? a : b) = mid;
            }
            m.vertices.push_back(centre + (b + lift) * d);
        }
    for (int i = 0; i < stacks; ++i)
        for (int j = 0; j < slices; ++j) {
            const int a = i * slices + j, b = i * slices + (j + 1) % slices, c = a + slices, d = b + slices;
            m.faces.emplace_back(a, c, d);
            m.faces.emplace_back(a, d, b);
        }
    // Close the poles with fans.
    const int top = static_cast<int>(m.vertices.size()), bottom = top + 1;
    double a = 0, b = 10;
    for (int k = 0; k < 80; ++k) ((o.distance(centre + 0.5 * (a + b) * Vec3::UnitZ()) < 0) ? a : b) = 0.5 * (a + b);
    m.vertices.push_back(centre + (b + lift) * Vec3::UnitZ());
    a = 0, b = 10;
    for (int k = 0; k < 80; ++k) ((o.distance(centre - 0.5 * (a + b) * Vec3::UnitZ()) < 0) ? a : b) = 0.5 * (a + b);
    m.vertices.push_back(centre - (b + lift) * Vec3::UnitZ());
    for (int j = 0; j < slices; ++j) {
        m.faces.emplace_back(top, j, (j + 1) % slices);
        m.faces.emplace_back(bottom, stacks * slices + (j + 1) % slices, stacks * slices + j);
    }
    return m;
}

/// Counts pixels whose colour is the obstacle's (red) rather than the cloth's (green).
int red_pixels(const Image& img)
{
    int n = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            const auto p = pixel(img, x, y);
            if (p[0] > p[1] + 20) ++n;
        }
    return n;
}

RenderOptions plain_options(int w, int h)
{
    RenderOptions o;
    o.width = w;
    o.height = h;
    o.background = Vec3::Zero();
    o.samples_per_pixel = 4;
    return o;
}

}  // namespace

// Every pixel whose 3 x 3 neighbourhood of pixel centres lies inside the mesh's pinhole
// projection (computed here independently, triangle by triangle) is cloth, every pixel whose
// neighbourhood lies wholly outside it is background, and the cloth's pixel count matches.
TEST(DrapeView, ClothPixelsAreWhereTheMeshProjects)
{
    const render::ClothSurface cloth = render::grid_surface(wavy_grid(21, 17), 21, 17, 2);
    render::DrapeScene scene;
    scene.cloth = cloth;
    scene.cloth_color = Vec3(0.8, 0.8, 0.8);
    const int W = 200, H = 150;
    const Camera cam = render::view_camera(scene, render::View::CORNER, double(W) / H);
    const Image img = render::render_drape(scene, cam, plain_options(W, H));
    ASSERT_EQ(img.width, W);
    ASSERT_EQ(img.height, H);
    ASSERT_EQ(img.rgb.size(), static_cast<std::size_t>(W) * H * 3);

    // Independent projection: pixel centre -> inside some projected triangle.
    const Vec3 f = (cam.target - cam.eye).normalized(), r = f.cross(cam.up).normalized(), u = r.cross(f);
    const double t = std::tan(0.5 * cam.fov_deg * kPi / 180);
    std::vector<Eigen::Vector2d> proj;
    for (const Vec3& p : cloth.mesh.vertices) {
        const Vec3 q = p - cam.eye;
        const double z = q.dot(f);
        proj.emplace_back((q.dot(r) / (z * t * W / H) + 1) * W / 2, (1 - q.dot(u) / (z * t)) * H / 2);
    }
    std::vector<char> inside(W * H, 0);
    for (const auto& face : cloth.mesh.faces) {
        const Eigen::Vector2d a = proj[face[0]], b = proj[face[1]], c = proj[face[2]];
        auto cross = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q) { return p.x() * q.y() - p.y() * q.x(); };
        const double area = cross(b - a, c - a);
        if (area == 0) continue;
        const int x0 = std::max(0, int(std::floor(std::min({a.x(), b.x(), c.x()})))),
                  x1 = std::min(W - 1, int(std::ceil(std::max({a.x(), b.x(), c.x()}))));
        const int y0 = std::max(0, int(std::floor(std::min({a.y(), b.y(), c.y()})))),
                  y1 = std::min(H - 1, int(std::ceil(std::max({a.y(), b.y(), c.y()}))));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const Eigen::Vector2d pc(x + 0.5, y + 0.5);
                const double s = area > 0 ? 1 : -1;
                if (s * cross(b - a, pc - a) >= 0 && s * cross(c - b, pc - b) >= 0 && s * cross(a - c, pc - c) >= 0) inside[y * W + x] = 1;
            }
    }
    int interior = 0, exterior = 0, covered = 0, drawn = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            int in = 0, n = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx < 0 || yy < 0 || xx >= W || yy >= H) continue;
                    in += inside[yy * W + xx];
                    ++n;
                }
            const auto p = pixel(img, x, y);
            const bool cloth_px = p[0] + p[1] + p[2] > 3 * 25;
            covered += inside[y * W + x];
            drawn += cloth_px;
            if (in == n) {
                ++interior;
                EXPECT_TRUE(cloth_px) << "pixel " << x << ", " << y << " should show the cloth";
            } else if (in == 0) {
                ++exterior;
                EXPECT_FALSE(cloth_px) << "pixel " << x << ", " << y << " should be background";
            }
        }
    EXPECT_GT(interior, W * H / 6);  // the cloth fills the frame (tight framing)...
    EXPECT_GT(exterior, W * H / 20);
    EXPECT_NEAR(drawn, covered, 0.03 * covered);  // ... and is drawn where it projects (edges anti-aliased)
}

// A closed cloth lying on an obstacle 1 mm off its surface is flat between its vertices: the
// obstacle's curved surface and its edges poke through it. None of the obstacle (red) shows
// through the cloth (green); with the cloth's priority switched off it does (so the check can fail).
TEST(DrapeView, ObstacleNeverShowsThroughClothLyingOnIt)
{
    const geometry::Sphere sphere(Vec3(0, 0, 0.5), 0.3);
    const geometry::Box box(Vec3(0, 0, 0.25), Vec3(0.25, 0.25, 0.25), 0.2);
    for (const geometry::Obstacle* o : {static_cast<const geometry::Obstacle*>(&sphere), static_cast<const geometry::Obstacle*>(&box)}) {
        const Vec3 c = o == &sphere ? sphere.centre() : box.centre();
        RenderMesh solid;
        solid.mesh = o->tessellate();
        solid.color = Vec3(1, 0, 0);
        RenderMesh cloth;
        cloth.mesh = wrap(*o, c, 1e-3, 40, 19);
        cloth.surface = render::Surface::CLOTH;
        cloth.color = Vec3(0, 1, 0);
        std::vector<Vec3> pts(cloth.mesh.vertices.begin(), cloth.mesh.vertices.end());
        for (const auto& [az, el] : {std::pair{-45.0, 20.0}, std::pair{-90.0, 12.0}, std::pair{30.0, 70.0}}) {
            const double a = az * kPi / 180, e = el * kPi / 180;
            const Camera cam = render::fit_camera(pts, -Vec3(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)),
                                                  Vec3::UnitZ(), 30, 4.0 / 3.0);
            RenderOptions opt = plain_options(160, 120);
            const Image img = render::render({solid, cloth}, cam, opt);
            EXPECT_EQ(red_pixels(img), 0) << o->kind() << " az " << az;
            if (const char* dir = std::getenv("WOVEN_TEST_PNG_DIR"))  // to look at the pictures
                render::write_png(img, std::string(dir) + "/through_" + o->kind() + std::to_string(int(az)) + ".png");
            opt.cloth_priority_m = -1;
            EXPECT_GT(red_pixels(render::render({solid, cloth}, cam, opt)), 20) << o->kind() << " az " << az;
        }
    }
}

// The priority is a short distance: a cloth well behind an obstacle stays hidden.
TEST(DrapeView, ClothBehindAnObstacleStaysHidden)
{
    RenderMesh solid;
    solid.mesh = geometry::Box(Vec3(0, 0, 0), Vec3(0.2, 0.2, 0.2)).tessellate();
    solid.color = Vec3(1, 0, 0);
    RenderMesh cloth;
    cloth.surface = render::Surface::CLOTH;
    cloth.color = Vec3(0, 1, 0);
    cloth.mesh = render::grid_surface(wavy_grid(11, 11), 11, 11, 1).mesh;  // 0.1 m spacing, 0.2 m behind the box
    for (auto& v : cloth.mesh.vertices) v = Vec3(v.x(), 0.4 + 0.1 * (v.z() - 0.4), v.y());
    Camera cam;
    cam.eye = Vec3(0, -3, 0);
    cam.target = Vec3::Zero();
    cam.fov_deg = 20;
    const Image img = render::render({solid, cloth}, cam, plain_options(120, 120));
    const auto centre = pixel(img, 60, 60);
    EXPECT_GT(centre[0], 60);
    EXPECT_EQ(centre[1], 0);
}

TEST(DrapeView, SameInputSameBytes)
{
    const geometry::Box box(Vec3(0, 0, 0.25), Vec3(0.25, 0.25, 0.25));
    geometry::ObstacleSet obstacles;
    obstacles.add(std::make_unique<geometry::Plane>(Vec3::Zero(), Vec3::UnitZ()));
    obstacles.add(std::make_unique<geometry::Box>(box));
    render::DrapeScene scene;
    scene.cloth = render::grid_surface(wavy_grid(15, 15), 15, 15, 3);
    scene.obstacles = &obstacles;
    RenderOptions opt;
    opt.width = 96;
    opt.height = 72;
    const Camera cam = render::view_camera(scene, render::View::FRONT, 96.0 / 72.0);
    const Image a = render::render_drape(scene, cam, opt), b = render::render_drape(scene, cam, opt);
    EXPECT_EQ(a.rgb, b.rgb);
}

// fit_camera: every point inside the frame (within `fill`), and some point on its border.
TEST(FitCamera, PointsFitTightly)
{
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> U(-1, 1);
    std::vector<Vec3> pts;
    for (int i = 0; i < 200; ++i) pts.emplace_back(U(rng), 0.5 * U(rng), 0.3 + 0.3 * U(rng));
    for (const Vec3& fwd : {Vec3(1, 2, -0.5), Vec3(0, 0, -1), Vec3(-1, 0.2, -0.3)}) {
        const double aspect = 4.0 / 3.0, fill = 0.9;
        const Vec3 up = std::abs(fwd.normalized().z()) > 0.99 ? Vec3::UnitY() : Vec3::UnitZ();
        const Camera cam = render::fit_camera(pts, fwd, up, 30, aspect, fill);
        const Vec3 f = (cam.target - cam.eye).normalized(), r = f.cross(cam.up).normalized(), u = r.cross(f);
        EXPECT_NEAR(f.dot(fwd.normalized()), 1.0, 1e-12);
        const double t = std::tan(15 * kPi / 180);
        double ex = 0, ey = 0;
        for (const Vec3& p : pts) {
            const Vec3 q = p - cam.eye;
            ASSERT_GT(q.dot(f), 0);
            ex = std::max(ex, std::abs(q.dot(r) / q.dot(f)) / (t * aspect));
            ey = std::max(ey, std::abs(q.dot(u) / q.dot(f)) / t);
        }
        EXPECT_LE(ex, fill + 1e-6);
        EXPECT_LE(ey, fill + 1e-6);
        EXPECT_GT(std::max(ex, ey), fill - 1e-3);
    }
}

// The refined surface passes through every particle and keeps a flat grid flat.
TEST(GridSurface, InterpolatesTheParticles)
{
    const int nu = 9, nv = 7, k = 3;
    const Positions x = wavy_grid(nu, nv);
    const render::ClothSurface s = render::grid_surface(x, nu, nv, k);
    const int mu = (nu - 1) * k + 1;
    ASSERT_EQ(s.mesh.vertices.size(), static_cast<std::size_t>(mu) * ((nv - 1) * k + 1));
    ASSERT_EQ(s.uv.size(), s.mesh.vertices.size());
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            EXPECT_NEAR((s.mesh.vertices[i * k + mu * j * k] - x[i + nu * j]).norm(), 0, 1e-12);
            EXPECT_NEAR((s.uv[i * k + mu * j * k] - Eigen::Vector2d(i, j)).norm(), 0, 1e-12);
        }
    Positions flat;
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) flat.emplace_back(0.02 * i, 0.02 * j, 0.3);
    const render::ClothSurface f = render::grid_surface(flat, nu, nv, 4);
    for (const Vec3& v : f.mesh.vertices) EXPECT_NEAR(v.z(), 0.3, 1e-12);
    EXPECT_NEAR(f.spacing_m, 0.02, 1e-12);
    EXPECT_THROW(render::grid_surface(flat, nu, nv + 1), InputError);
    EXPECT_THROW(render::grid_surface(flat, nu, nv, 0), InputError);
}

TEST(Views, NamesRoundTrip)
{
    for (const char* n : {"scene", "front", "corner", "side", "top"}) {
        const auto v = render::parse_view(n);
        ASSERT_TRUE(v.has_value()) << n;
        EXPECT_EQ(render::view_name(*v), n);
    }
    EXPECT_FALSE(render::parse_view("back").has_value());
}
