// render / frame_box: silhouette geometry against the pinhole projection, shading, shadows, determinism.
#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "woven/common/error.hpp"
#include "woven/render/raytracer.hpp"

using namespace woven;
using render::Camera;
using render::frame_box;
using render::Image;
using render::RenderMesh;
using render::RenderOptions;

namespace {

constexpr double kPi = 3.14159265358979323846;

geometry::TriangleMesh uv_sphere(const Vec3& centre, double r, int slices = 128, int stacks = 64)
{
    geometry::TriangleMesh m;
    for (int i = 0; i <= stacks; ++i) {
        const double th = kPi * i / stacks;
        for (int j = 0; j < slices; ++j) {
            const double ph = 2 * kPi * j / slices;
            m.vertices.push_back(centre + r * Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
        }
    }
    for (int i = 0; i < stacks; ++i)
        for (int j = 0; j < slices; ++j) {
            const int a = i * slices + j, b = i * slices + (j + 1) % slices;
            const int c = a + slices, d = b + slices;
            m.faces.emplace_back(a, c, d);
            m.faces.emplace_back(a, d, b);
        }
    return m;
}

/// A square in the plane z = height, side 2 * half, wound counter-clockwise seen from +z.
geometry::TriangleMesh square(double half, double height = 0, int n = 1)
{
    geometry::TriangleMesh m;
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) m.vertices.emplace_back(-half + 2 * half * j / n, -half + 2 * half * i / n, height);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const int a = i * (n + 1) + j;
            m.faces.emplace_back(a, a + 1, a + n + 2);
            m.faces.emplace_back(a, a + n + 2, a + n + 1);
        }
    return m;
}

int grey(const Image& img, int x, int y) { return img.rgb[(static_cast<std::size_t>(y) * img.width + x) * 3]; }

}  // namespace

TEST(Render, SphereSilhouetteMatchesPinholeProjection)
{
    RenderMesh sphere;
    sphere.mesh = uv_sphere(Vec3::Zero(), 1.0);
    sphere.color = Vec3(0.5, 0.5, 0.5);
    const double d = 5;
    Camera cam;
    cam.eye = Vec3(d, 0, 0);
    cam.target = Vec3::Zero();
    cam.fov_deg = 35;
    RenderOptions opt;
    opt.width = 241;
    opt.height = 201;
    opt.light_dir = Vec3(1, 0, 0);  // from the camera
    const Image img = render::render({sphere}, cam, opt);
    ASSERT_EQ(img.width, 241);
    ASSERT_EQ(img.height, 201);
    ASSERT_EQ(img.rgb.size(), 241u * 201u * 3u);

    const double expected = std::tan(std::asin(1 / d)) / std::tan(0.5 * 35 * kPi / 180) * opt.height / 2;
    const int cx = 120, cy = 100;
    // Horizontal and vertical extents of the non-background pixels through the centre.
    int left = cx, right = cx, topy = cy, bottomy = cy;
    while (left > 0 && grey(img, left - 1, cy) < 250) --left;
    while (right < img.width - 1 && grey(img, right + 1, cy) < 250) ++right;
    while (topy > 0 && grey(img, cx, topy - 1) < 250) --topy;
    while (bottomy < img.height - 1 && grey(img, cx, bottomy + 1) < 250) ++bottomy;
    EXPECT_NEAR((right - left + 1) / 2.0, expected, 2.0);
    EXPECT_NEAR((bottomy - topy + 1) / 2.0, expected, 2.0);
    EXPECT_EQ(grey(img, 2, 2), 255);  // background corner

    // Lit head-on: the centre is brighter than the limb just inside the silhouette.
    EXPECT_GT(grey(img, cx, cy), grey(img, left + 3, cy) + 25);
    EXPECT_GT(grey(img, cx, cy), grey(img, cx, topy + 3) + 25);
}

TEST(Render, FloorUnderAnOccluderIsShadowed)
{
    RenderMesh floor;
    floor.mesh = square(5.0);
    floor.color = Vec3(0.8, 0.8, 0.8);
    RenderMesh ball;
    ball.mesh = uv_sphere(Vec3(0, 0, 1), 0.5, 48, 24);
    Camera cam;
    cam.eye = Vec3(0, 0, 10);
    cam.target = Vec3::Zero();
    cam.up = Vec3::UnitY();
    cam.fov_deg = 40;
    RenderOptions opt;
    opt.width = opt.height = 200;
    opt.light_dir = Vec3(1, 0, 1).normalized();  // shadow centred on (-1, 0, 0)
    auto column = [&](double x) { return static_cast<int>(std::floor(opt.width / 2.0 * (1 + x / (10 * std::tan(20 * kPi / 180))))); };
    const Image lit_img = render::render({floor, ball}, cam, opt);
    const int shadow = grey(lit_img, column(-1.0), 100), lit = grey(lit_img, column(1.5), 100);
    EXPECT_LT(shadow + 60, lit) << "shadow " << shadow << " lit " << lit;

    opt.shadows = false;
    opt.ambient_occlusion = false;
    const Image flat = render::render({floor, ball}, cam, opt);
    EXPECT_NEAR(grey(flat, column(-1.0), 100), grey(flat, column(1.5), 100), 2);
}

TEST(Render, DeterministicBytes)
{
    RenderMesh cloth;
    cloth.mesh = square(1.0, 0.3, 20);
    cloth.surface = render::Surface::CLOTH;
    cloth.color = Vec3(0.6, 0.2, 0.2);
    for (const Vec3& v : cloth.mesh.vertices) cloth.uv.emplace_back(10 * (v.x() + 1), 10 * (v.y() + 1));
    for (auto& v : cloth.mesh.vertices) v.z() += 0.1 * std::sin(4 * v.x()) * std::cos(3 * v.y());
    RenderMesh floor;
    floor.mesh = square(4.0);
    const Camera cam = frame_box(Vec3(-1, -1, 0), Vec3(1, 1, 0.5));
    RenderOptions opt;
    opt.width = 160;
    opt.height = 120;
    const Image a = render::render({floor, cloth}, cam, opt);
    const Image b = render::render({floor, cloth}, cam, opt);
    EXPECT_EQ(a.rgb, b.rgb);
}

// Seen from its back the cloth is lit as from its front (two-sided), kClothBackShade darker.
TEST(Render, ClothIsTwoSided)
{
    RenderMesh cloth;
    cloth.mesh = square(1.0);
    cloth.surface = render::Surface::CLOTH;
    Camera cam;
    cam.eye = Vec3(0, 0, 5);
    cam.target = Vec3::Zero();
    cam.up = Vec3::UnitY();
    RenderOptions opt;
    opt.width = opt.height = 64;
    opt.light_dir = Vec3(0, 0, 1);
    opt.light_radius_deg = 0;
    const Image front = render::render({cloth}, cam, opt);
    for (auto& f : cloth.mesh.faces) std::swap(f[1], f[2]);  // normals point down, away from the camera
    const Image back = render::render({cloth}, cam, opt);
    auto linear = [](int c) { return std::pow(c / 255.0, 2.2); };
    // Lit head-on, unoccluded: albedo 0.7 times key + sky in front (0.96 linear), 0.8 times that behind.
    EXPECT_NEAR(linear(grey(front, 32, 32)), 0.7 * (opt.light + opt.sky), 0.01);
    EXPECT_NEAR(linear(grey(back, 32, 32)) / linear(grey(front, 32, 32)), 0.8, 0.02);
}

TEST(Render, EmptySceneNonFiniteVerticesAndBadInput)
{
    RenderOptions opt;
    opt.width = 32;
    opt.height = 24;
    opt.background = Vec3(0, 0, 0);
    Camera cam;
    cam.eye = Vec3(3, 0, 0);
    cam.target = Vec3::Zero();
    const Image empty = render::render({}, cam, opt);
    EXPECT_EQ(empty.rgb, std::vector<std::uint8_t>(32 * 24 * 3, 0));

    RenderMesh m;
    m.mesh = square(1.0, 0, 4);
    m.mesh.vertices[7].x() = std::numeric_limits<double>::quiet_NaN();
    EXPECT_NO_THROW(render::render({m}, cam, opt));

    m.mesh.faces.emplace_back(0, 1, 999);
    EXPECT_THROW(render::render({m}, cam, opt), InputError);
    opt.width = 0;
    EXPECT_THROW(render::render({}, cam, opt), InputError);
    opt.width = 32;
    cam.target = cam.eye;
    EXPECT_THROW(render::render({}, cam, opt), InputError);
}

TEST(FrameBox, BoxCornersProjectInsideTheImage)
{
    const Vec3 lo(-0.5, -0.3, 0), hi(0.5, 0.3, 0.8);
    const Camera cam = frame_box(lo, hi);
    EXPECT_NEAR(((cam.target - 0.5 * (lo + hi)).norm()), 0, 1e-12);
    EXPECT_GT(cam.eye.z(), cam.target.z());  // elevated
    const Vec3 f = (cam.target - cam.eye).normalized();
    const Vec3 r = f.cross(cam.up).normalized(), u = r.cross(f);
    const double t = std::tan(0.5 * cam.fov_deg * kPi / 180);
    double extent = 0;
    for (int i = 0; i < 8; ++i) {
        const Vec3 c((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(), (i & 4) ? hi.z() : lo.z());
        const Vec3 q = c - cam.eye;
        const double sy = q.dot(u) / q.dot(f) / t;  // -1..1 over the image height
        const double sx = q.dot(r) / q.dot(f) / t;  // -aspect..aspect
        EXPECT_LE(std::abs(sy), 0.9 + 1e-9);
        EXPECT_LE(std::abs(sx), 0.9 + 1e-9);
        extent = std::max({extent, std::abs(sy), std::abs(sx)});
    }
    EXPECT_GT(extent, 0.85);  // and it is framed tightly (90 % of the half height)
}
