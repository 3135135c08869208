// MeshObstacle: agreement with the analytic primitives, the chair asset, open meshes, input checks.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>

#include "test_support.hpp"
#include "woven/common/error.hpp"
#include "woven/geometry/mesh_obstacle.hpp"
#include "woven/geometry/mesh_ops.hpp"
#include "woven/geometry/primitives.hpp"

namespace woven::geometry {
namespace {

using testing::expect_consistent_closest;
using testing::expect_contact_consistent;

/// Minimal OBJ reader (v and triangular f lines) for the chair asset.
TriangleMesh read_obj(const std::string& path)
{
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot open " + path);
    TriangleMesh m;
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream s(line);
        std::string tag;
        s >> tag;
        if (tag == "v") {
            Vec3 v;
            s >> v.x() >> v.y() >> v.z();
            m.vertices.push_back(v);
        } else if (tag == "f") {
            Eigen::Vector3i f;
            s >> f[0] >> f[1] >> f[2];
            m.faces.push_back(f - Eigen::Vector3i::Ones());
        }
    }
    return m;
}

const std::string kChair = std::string(WOVEN_SOURCE_DIR) + "/assets/chair.obj";

/// Exact unsigned distance to the mesh by brute force.
double brute_distance(const TriangleMesh& m, const Vec3& p)
{
    double best = std::numeric_limits<double>::infinity();
    for (const auto& f : m.faces) {
        // Minimise over the triangle by its closest point (barycentric projection with clamping
        // done through a tiny independent implementation: sample-free, Eberly's region test is
        // overkill here, so project onto the plane and fall back to the three edges).
        const Vec3 a = m.vertices[f[0]], b = m.vertices[f[1]], c = m.vertices[f[2]];
        const Vec3 n = (b - a).cross(c - a);
        const double nn = n.squaredNorm();
        if (nn == 0) continue;
        const Vec3 q = p - n * (n.dot(p - a) / nn);
        const double u = (b - q).cross(c - q).dot(n) / nn, v = (c - q).cross(a - q).dot(n) / nn;
        if (u >= 0 && v >= 0 && u + v <= 1) {
            best = std::min(best, (p - q).norm());
            continue;
        }
        for (const auto& [e0, e1] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
            const double s = std::clamp((p - e0).dot(e1 - e0) / (e1 - e0).squaredNorm(), 0.0, 1.0);
            best = std::min(best, (p - (e0 + s * (e1 - e0))).norm());
        }
    }
    return best;
}

/// Inside test by ray parity along a fixed, irrational-ish direction.
bool inside_by_parity(const TriangleMesh& m, const Vec3& p)
{
    const Vec3 d = Vec3(0.5773, 0.3141, 0.7537).normalized();
    int crossings = 0;
    for (const auto& f : m.faces) {
        const Vec3 a = m.vertices[f[0]], b = m.vertices[f[1]], c = m.vertices[f[2]];
        const Vec3 e1 = b - a, e2 = c - a, h = d.cross(e2);
        const double det = e1.dot(h);
        if (std::abs(det) < 1e-300) continue;
        const Vec3 s = p - a;
        const double u = s.dot(h) / det;
        if (u < 0 || u > 1) continue;
        const Vec3 q = s.cross(e1);
        const double v = d.dot(q) / det;
        if (v < 0 || u + v > 1) continue;
        if (e2.dot(q) / det > 0) ++crossings;
    }
    return crossings % 2 == 1;
}

TEST(MeshObstacle, TessellatedBoxIsExact)
{
    const Box box(Vec3(0.2, -0.1, 0.4), Vec3(0.3, 0.5, 0.2), 0.4);
    const MeshObstacle mesh(box.tessellate());
    EXPECT_TRUE(mesh.closed());
    EXPECT_EQ(mesh.kind(), "mesh");
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int i = 0; i < 500; ++i) {
        const Vec3 p(0.2 + u(rng), -0.1 + u(rng), 0.4 + u(rng));
        EXPECT_NEAR(mesh.distance(p), box.distance(p), 1e-12) << p.transpose();
        const ClosestPoint c = mesh.closest(p), e = box.closest(p);
        EXPECT_LT((c.point - e.point).norm(), 1e-9) << p.transpose();
        if (i < 100) expect_consistent_closest(mesh, p);
    }
    // Segments: the same contact parameter as the analytic slab test.
    int hits = 0;
    for (int i = 0; i < 300; ++i) {
        const Vec3 p0(0.2 + u(rng), -0.1 + u(rng), 0.4 + u(rng)), p1(0.2 + u(rng), -0.1 + u(rng), 0.4 + u(rng));
        if (box.distance(p0) <= 0) continue;
        const auto tm = mesh.first_contact(p0, p1), tb = box.first_contact(p0, p1);
        ASSERT_EQ(tm.has_value(), tb.has_value()) << p0.transpose() << " -> " << p1.transpose();
        if (tm) {
            ++hits;
            EXPECT_NEAR(*tm, *tb, 1e-12);
        }
    }
    EXPECT_GT(hits, 30);
    EXPECT_EQ(mesh.first_contact(Vec3(0.2, -0.1, 0.4), Vec3(3, 0, 0)), 0.0);  // starts inside
}

TEST(MeshObstacle, TessellatedSphereAndCylinderWithinTessellationError)
{
    const Sphere sphere(Vec3(0.1, 0.0, -0.2), 0.4, 64);
    const Cylinder cyl(Vec3(0, 0, 0), 0.3, 0.5, Vec3(0, 1, 0), 64);
    // Vertices lie on the surface; faces are inside by at most the sagitta of the largest cell.
    const double sphere_tol = 0.4 * (1 - std::cos(2 * std::numbers::pi / 64));
    const double cyl_tol = 0.3 * (1 - std::cos(std::numbers::pi / 64));
    const MeshObstacle ms(sphere.tessellate()), mc(cyl.tessellate());
    EXPECT_TRUE(ms.closed());
    EXPECT_TRUE(mc.closed());
    std::mt19937 rng(12);
    std::uniform_real_distribution<double> u(-0.8, 0.8);
    double worst_s = 0, worst_c = 0;
    for (int i = 0; i < 500; ++i) {
        const Vec3 p(u(rng), u(rng), u(rng));
        worst_s = std::max(worst_s, std::abs(ms.distance(p) - sphere.distance(p)));
        worst_c = std::max(worst_c, std::abs(mc.distance(p) - cyl.distance(p)));
        EXPECT_EQ(ms.distance(p) < 0, inside_by_parity(ms.mesh(), p)) << p.transpose();
    }
    EXPECT_LT(worst_s, sphere_tol);
    EXPECT_LT(worst_c, cyl_tol);
    EXPECT_GT(worst_s, 1e-5);  // the check above compares different surfaces, not the same code
    const auto t = ms.first_contact(Vec3(0.1, 0, 2), Vec3(0.1, 0, -2));
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, *sphere.first_contact(Vec3(0.1, 0, 2), Vec3(0.1, 0, -2)), 1e-12);  // pole is a vertex
}

TEST(MeshObstacle, ChairAssetIsClosedAndShaped)
{
    ASSERT_TRUE(std::filesystem::exists(kChair)) << kChair;
    EXPECT_LT(std::filesystem::file_size(kChair), 1u << 20);
    const TriangleMesh m = read_obj(kChair);
    EXPECT_GE(m.faces.size(), 2000u);
    EXPECT_LE(m.faces.size(), 20000u);
    EXPECT_TRUE(is_closed(m));
    EXPECT_GT(signed_volume(m), 0.0);
    const MeshObstacle chair(m);
    EXPECT_TRUE(chair.closed());
    const Aabb b = chair.bounds();
    EXPECT_NEAR(b.lo.z(), 0.0, 1e-6);
    EXPECT_NEAR(b.hi.z(), 0.80, 0.01);
    EXPECT_NEAR(b.hi.x() - b.lo.x(), 0.80, 0.02);
    EXPECT_NEAR(b.hi.y() - b.lo.y(), 0.85, 0.02);
    EXPECT_NEAR(0.5 * (b.lo.x() + b.hi.x()), 0.0, 0.01);
    // Seat top at 0.42 m: a drop onto the middle of the seat cushion.
    const auto t = chair.first_contact(Vec3(0, -0.1, 1.5), Vec3(0, -0.1, 0.0));
    ASSERT_TRUE(t);
    EXPECT_NEAR(1.5 - 1.5 * *t, 0.42, 1e-6);
    // Backrest is behind the seat (+y): a horizontal push from the front hits it after the seat.
    const auto tb = chair.first_contact(Vec3(0, -1.0, 0.6), Vec3(0, 1.0, 0.6));
    ASSERT_TRUE(tb);
    EXPECT_GT(-1.0 + 2.0 * *tb, 0.15);
}

TEST(MeshObstacle, ChairSignedDistance)
{
    const TriangleMesh m = read_obj(kChair);
    const MeshObstacle chair(m);
    EXPECT_LT(chair.distance(Vec3(0, -0.1, 0.36)), -0.04);  // inside the seat cushion
    EXPECT_NEAR(chair.distance(Vec3(0, -0.1, 0.60)), 0.18, 1e-6);  // above the seat
    EXPECT_LT(chair.distance(Vec3(0, 0.37, 0.6)), -0.04);  // inside the backrest
    EXPECT_LT(chair.distance(Vec3(0.335, -0.2, 0.4)), -0.04);  // inside the right arm
    EXPECT_GT(chair.distance(Vec3(0, 0, 0.04)), 0.0);  // under the seat, between the legs
    EXPECT_GT(chair.distance(Vec3(0, 0, 2.0)), 1.1);
    // Against brute force: magnitude and sign (ray parity) at random points around the chair.
    std::mt19937 rng(13);
    std::uniform_real_distribution<double> ux(-0.5, 0.5), uy(-0.5, 0.5), uz(-0.05, 0.9);
    int inside = 0;
    for (int i = 0; i < 300; ++i) {
        const Vec3 p(ux(rng), uy(rng), uz(rng));
        const double d = chair.distance(p);
        EXPECT_NEAR(std::abs(d), brute_distance(m, p), 1e-9) << p.transpose();
        const bool in = inside_by_parity(m, p);
        EXPECT_EQ(d < 0, in) << p.transpose();
        inside += in;
        if (i < 60 && std::abs(d) > 1e-4) expect_consistent_closest(chair, p, 1e-5);
    }
    EXPECT_GT(inside, 30);
    EXPECT_LT(inside, 270);
}

TEST(MeshObstacle, ChairFirstContactAgreesWithDenseSampling)
{
    const MeshObstacle chair(read_obj(kChair));
    std::mt19937 rng(14);
    std::uniform_real_distribution<double> u(-0.6, 0.6), uz(0.0, 1.0);
    int hits = 0;
    for (int i = 0; i < 150; ++i) {
        const Vec3 p0(u(rng), u(rng), uz(rng)), p1(u(rng), u(rng), uz(rng));
        if (chair.distance(p0) <= 0) continue;
        if (expect_contact_consistent(chair, p0, p1, 4000)) ++hits;
    }
    EXPECT_GT(hits, 30);
}

TEST(MeshObstacle, OpenMeshIsUnsignedShell)
{
    // A unit square in z = 0 (two triangles): distance is |z| above and below.
    TriangleMesh m;
    m.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
    m.faces = {Eigen::Vector3i(0, 1, 2), Eigen::Vector3i(0, 2, 3)};
    const MeshObstacle sheet(m);
    EXPECT_FALSE(sheet.closed());
    EXPECT_NEAR(sheet.distance(Vec3(0.3, 0.6, 0.2)), 0.2, 1e-15);
    EXPECT_NEAR(sheet.distance(Vec3(0.3, 0.6, -0.2)), 0.2, 1e-15);
    EXPECT_NEAR(sheet.distance(Vec3(1.3, 0.5, 0.4)), 0.5, 1e-15);
    EXPECT_LT((sheet.closest(Vec3(0.3, 0.6, -0.2)).normal - Vec3(0, 0, -1)).norm(), 1e-15);
    expect_consistent_closest(sheet, Vec3(1.3, 0.5, 0.4));
    // Segments crossing from either side are caught; a segment leaving the sheet is not.
    auto t = sheet.first_contact(Vec3(0.5, 0.5, 1), Vec3(0.5, 0.5, -1));
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, 0.5, 1e-15);
    t = sheet.first_contact(Vec3(0.5, 0.5, -1), Vec3(0.5, 0.5, 3));
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, 0.25, 1e-15);
    EXPECT_FALSE(sheet.first_contact(Vec3(1.5, 0.5, 1), Vec3(1.5, 0.5, -1)));
    // An open box (top removed) is open too: inside it the distance stays positive.
    TriangleMesh box = Box(Vec3::Zero(), Vec3(1, 1, 1)).tessellate();
    std::erase_if(box.faces, [&](const Eigen::Vector3i& f) {
        return box.vertices[f[0]].z() > 0 && box.vertices[f[1]].z() > 0 && box.vertices[f[2]].z() > 0;
    });
    EXPECT_EQ(box.faces.size(), 10u);
    const MeshObstacle cup(box);
    EXPECT_FALSE(cup.closed());
    EXPECT_NEAR(cup.distance(Vec3(0, 0, 0.5)), 1.0, 1e-15);
}

TEST(MeshObstacle, InwardFacingClosedMeshIsTreatedAsOutward)
{
    TriangleMesh m = Box(Vec3::Zero(), Vec3(1, 1, 1)).tessellate();
    for (auto& f : m.faces) std::swap(f[1], f[2]);
    const MeshObstacle mesh(m);
    EXPECT_TRUE(mesh.closed());
    EXPECT_NEAR(mesh.distance(Vec3(0, 0, 0.5)), -0.5, 1e-15);
    EXPECT_NEAR(mesh.distance(Vec3(0, 0, 1.5)), 0.5, 1e-15);
    EXPECT_GT(signed_volume(mesh.tessellate()), 0.0);
    const auto t = mesh.first_contact(Vec3(0, 0, 3), Vec3(0, 0, -3));
    ASSERT_TRUE(t);
    EXPECT_NEAR(*t, 1.0 / 3.0, 1e-15);
}

TEST(MeshObstacle, BadInputThrowsInputError)
{
    TriangleMesh empty;
    EXPECT_THROW(MeshObstacle{empty}, InputError);
    TriangleMesh no_faces;
    no_faces.vertices = {Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY()};
    EXPECT_THROW(MeshObstacle{no_faces}, InputError);
    TriangleMesh out_of_range = no_faces;
    out_of_range.faces = {Eigen::Vector3i(0, 1, 3)};
    EXPECT_THROW(MeshObstacle{out_of_range}, InputError);
    TriangleMesh negative = no_faces;
    negative.faces = {Eigen::Vector3i(0, -1, 2)};
    EXPECT_THROW(MeshObstacle{negative}, InputError);
    TriangleMesh nan = no_faces;
    nan.faces = {Eigen::Vector3i(0, 1, 2)};
    nan.vertices[1].x() = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(MeshObstacle{nan}, InputError);
    TriangleMesh degenerate;
    degenerate.vertices = {Vec3::Zero(), Vec3::UnitX(), 2 * Vec3::UnitX()};
    degenerate.faces = {Eigen::Vector3i(0, 1, 2)};
    EXPECT_THROW(MeshObstacle{degenerate}, InputError);
    TriangleMesh ok = no_faces;
    ok.faces = {Eigen::Vector3i(0, 1, 2)};
    EXPECT_NO_THROW(MeshObstacle{ok});
}

}  // namespace
}  // namespace woven::geometry
