// A cloth of any outline: outline geometry (areas, containment, self-intersection, clipping,
// triangulation) and the grid cut (kept particles, areas summing to the outline's, the flat
// surface being the outline, and every documented error).
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "woven/common/error.hpp"
#include "woven/kes/fabric.hpp"
#include "woven/model/cloth_model.hpp"
#include "woven/model/outline.hpp"

using ::testing::HasSubstr;
using woven::InputError;
using woven::Positions;
using woven::Vec2;
using woven::Vec3;
namespace m = woven::model;

namespace {

constexpr double kPi = std::numbers::pi;

m::Grid grid(int nu, int nv, double sigma)
{
    m::Grid g;
    g.nu = nu;
    g.nv = nv;
    g.sigma = sigma;
    return g;
}

Positions flat(const m::Grid& g, double z = 0.2)
{
    Positions x(g.size());
    for (int j = 0; j < g.nv; ++j)
        for (int i = 0; i < g.nu; ++i) {
            const Vec2 uv = m::rest_uv(g, i, j);
            x[g.index(i, j)] = Vec3(uv.x(), uv.y(), z);
        }
    return x;
}

double mesh_area(const woven::geometry::TriangleMesh& mesh)
{
    double a = 0;
    for (const auto& f : mesh.faces)
        a += 0.5 * (mesh.vertices[f[1]] - mesh.vertices[f[0]]).cross(mesh.vertices[f[2]] - mesh.vertices[f[0]]).norm();
    return a;
}

double sum(const std::vector<double>& v)
{
    double s = 0;
    for (double x : v) s += x;
    return s;
}

m::Outline disc(double r, Vec2 c = Vec2::Zero())
{
    m::Outline o;
    o.kind = m::Outline::Kind::DISC;
    o.radius = r;
    o.centre = c;
    return o;
}

m::Outline polygon(std::vector<Vec2> pts)
{
    m::Outline o;
    o.kind = m::Outline::Kind::POLYGON;
    o.points = std::move(pts);
    return o;
}

void expect_error(const m::Grid& g, const m::Outline& o, const std::string& field, const std::string& what)
{
    try {
        m::cut_grid(g, o, "scene.toml", "cloth.outline");
        ADD_FAILURE() << "no error, expected " << what;
    } catch (const InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr("scene.toml: " + field + ": "));
        EXPECT_THAT(e.what(), HasSubstr(what));
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    }
}

}  // namespace

TEST(Outline, RingAreasAreExact)
{
    const m::Grid g = grid(41, 41, 0.01);
    EXPECT_NEAR(m::signed_area(m::outline_ring(disc(0.15), g)), kPi * 0.0225, 1e-15);
    m::Outline a = disc(0.15);
    a.kind = m::Outline::Kind::ANNULUS;
    a.inner_radius = 0.05;
    EXPECT_NEAR(m::signed_area(m::outline_ring(a, g)), kPi * (0.0225 - 0.0025), 1e-15);
    // A clockwise polygon is turned counter-clockwise.
    const m::Ring sq = m::outline_ring(polygon({{0, 0}, {0, 0.1}, {0.1, 0.1}, {0.1, 0}}), g);
    EXPECT_NEAR(m::signed_area(sq), 0.01, 1e-16);
    EXPECT_NEAR(m::signed_area(m::outline_ring(m::Outline{}, g)), 0.4 * 0.4, 1e-15);
}

TEST(Outline, ContainsAndSelfIntersection)
{
    const m::Ring sq = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    EXPECT_TRUE(m::contains(sq, {0.5, 0.5}));
    EXPECT_FALSE(m::contains(sq, {1.5, 0.5}));
    EXPECT_FALSE(m::self_intersection(sq));
    const m::Ring bowtie = {{0, 0}, {1, 1}, {1, 0}, {0, 1}};
    ASSERT_TRUE(m::self_intersection(bowtie));
    EXPECT_EQ(*m::self_intersection(bowtie), std::make_pair(0, 2));
    // Touching itself at a vertex, and folding back along an edge, are intersections too.
    EXPECT_TRUE(m::self_intersection(m::Ring{{0, 0}, {2, 0}, {2, 2}, {1, 0}, {0, 2}}));
    EXPECT_TRUE(m::self_intersection(m::Ring{{0, 0}, {2, 0}, {1, 0}, {1, 1}}));
    // A concave (L-shaped) polygon is simple.
    EXPECT_FALSE(m::self_intersection(m::Ring{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}));
}

TEST(Outline, ClipAndTriangulateKeepArea)
{
    // A square rotated 45 degrees (diamond of half-diagonal 1) clipped to [0, 1]^2: a quarter.
    const m::Ring diamond = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    const m::Ring q = m::clip_to_box(diamond, {0, 0}, {1, 1});
    EXPECT_NEAR(m::signed_area(q), 0.5, 1e-15);
    // A U shape crossing a box twice: one polygon with a bridge, area exact, triangulated exactly.
    const m::Ring u = {{0, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}};
    const m::Ring c = m::clip_to_box(u, {-1, 2}, {4, 4});
    EXPECT_NEAR(m::signed_area(c), 2.0, 1e-14);
    for (const m::Ring& p : {u, c, m::outline_ring(disc(0.1), grid(31, 31, 0.01))}) {
        double a = 0;
        for (const auto& t : m::triangulate(p)) {
            const double ta = 0.5 * ((t[1] - t[0]).x() * (t[2] - t[0]).y() - (t[1] - t[0]).y() * (t[2] - t[0]).x());
            EXPECT_GE(ta, -1e-15);
            a += ta;
        }
        EXPECT_NEAR(a, m::signed_area(p), 1e-12 * std::abs(m::signed_area(p)));
    }
}

TEST(Outline, RectangleHasConsistentAreas)
{
    const m::Grid g = grid(5, 4, 0.1);
    const m::ClothCut c = m::cut_grid(g, m::Outline{}, "s", "f");
    EXPECT_EQ(c.count, 20);
    EXPECT_NEAR(c.area[g.index(2, 1)], 0.01, 1e-15);    // interior: sigma^2
    EXPECT_NEAR(c.area[g.index(0, 1)], 0.005, 1e-15);   // edge: half
    EXPECT_NEAR(c.area[g.index(4, 3)], 0.0025, 1e-15);  // corner: a quarter
    EXPECT_NEAR(sum(c.area), 0.4 * 0.3, 1e-15);
    EXPECT_NEAR(c.total_area, 0.12, 1e-15);
}

struct DiscCase {
    double radius, sigma, cx, cy;
};
class DiscCut : public ::testing::TestWithParam<DiscCase> {};

TEST_P(DiscCut, MassesSumToTheDiscAndTheFlatSurfaceIsTheDisc)
{
    const DiscCase p = GetParam();
    const int n = 2 * static_cast<int>(std::ceil((p.radius + std::abs(p.cx) + std::abs(p.cy)) / p.sigma)) + 3;
    const m::Grid g = grid(n, n, p.sigma);
    const m::ClothCut c = m::cut_grid(g, disc(p.radius, {p.cx, p.cy}), "s", "f");
    const double A = kPi * p.radius * p.radius;
    EXPECT_NEAR(c.total_area, A, 1e-14);
    EXPECT_NEAR(sum(c.area), A, 1e-12 * A);
    int inside = 0;
    for (int j = 0; j < g.nv; ++j)
        for (int i = 0; i < g.nu; ++i) {
            const double r = (m::rest_uv(g, i, j) - Vec2(p.cx, p.cy)).norm();
            const int k = g.index(i, j);
            if (std::abs(r - p.radius) > 1e-4 * p.radius) {
                EXPECT_EQ(c.active[k], r < p.radius ? 1 : 0) << i << " " << j;
            }
            if (!c.active[k]) {
                EXPECT_EQ(c.area[k], 0.0);
            }
            if (c.active[k] && r < p.radius - p.sigma) {
                EXPECT_NEAR(c.area[k], p.sigma * p.sigma, 1e-15);
            }
            inside += c.active[k];
        }
    EXPECT_EQ(c.count, inside);
    // The flat surface is the outline, and lies at the cloth's height.
    const auto mesh = m::cut_surface(g, c, flat(g));
    EXPECT_NEAR(mesh_area(mesh), A, 1e-12 * A);
    for (const auto& v : mesh.vertices) EXPECT_NEAR(v.z(), 0.2, 1e-15);
}

INSTANTIATE_TEST_SUITE_P(Outline, DiscCut,
                         ::testing::Values(DiscCase{0.15, 0.01, 0, 0}, DiscCase{0.15, 0.005, 0, 0}, DiscCase{0.1234, 0.007, 0.0031, -0.002},
                                           DiscCase{0.02, 0.01, 0.004, 0.0}));

TEST(Outline, AnnulusAndPolygonCuts)
{
    const m::Grid g = grid(41, 41, 0.01);
    m::Outline a = disc(0.15);
    a.kind = m::Outline::Kind::ANNULUS;
    a.inner_radius = 0.055;
    const m::ClothCut c = m::cut_grid(g, a, "s", "f");
    const double A = kPi * (0.15 * 0.15 - 0.055 * 0.055);
    EXPECT_NEAR(sum(c.area), A, 1e-12 * A);
    EXPECT_EQ(c.active[g.index(20, 20)], 0);  // the hole's centre
    EXPECT_EQ(c.active[g.index(20, 30)], 1);  // 0.10 m up: in the ring
    EXPECT_NEAR(mesh_area(m::cut_surface(g, c, flat(g))), A, 1e-10 * A);

    // An L-shaped garment-like panel, off the lattice.
    const m::Outline l =
        polygon({{-0.153, -0.147}, {0.1213, -0.147}, {0.1213, 0.0117}, {0.0023, 0.0117}, {0.0023, 0.1466}, {-0.153, 0.1466}});
    const m::ClothCut cl = m::cut_grid(g, l, "s", "f");
    const double AL = m::signed_area(m::outline_ring(l, g));
    EXPECT_NEAR(AL, 0.2743 * 0.1587 + 0.1553 * 0.1349, 1e-12);
    EXPECT_NEAR(sum(cl.area), AL, 1e-12);
    EXPECT_NEAR(mesh_area(m::cut_surface(g, cl, flat(g))), AL, 1e-12);
}

TEST(Outline, DroppedCornersAreExtrapolatedAlongThreads)
{
    // A tilted flat cloth (a plane z = 0.3 x + 0.1 y + 0.2): the surface's extrapolated corners lie
    // on the same plane, so its area is the outline's times the plane's stretch factor.
    const m::Grid g = grid(35, 35, 0.01);
    const m::ClothCut c = m::cut_grid(g, disc(0.16), "s", "f");
    Positions x = flat(g);
    for (auto& p : x) p.z() = 0.2 + 0.3 * p.x() + 0.1 * p.y();
    const double stretch = std::sqrt(1 + 0.09 + 0.01);
    EXPECT_NEAR(mesh_area(m::cut_surface(g, c, x)), kPi * 0.16 * 0.16 * stretch, 1e-12);
}

TEST(Outline, ErrorsNameTheField)
{
    const m::Grid g = grid(31, 31, 0.01);
    expect_error(g, disc(0.0), "cloth.outline.radius_m", "positive radius");
    expect_error(g, disc(NAN), "cloth.outline.radius_m", "positive radius");
    m::Outline a = disc(0.1);
    a.kind = m::Outline::Kind::ANNULUS;
    a.inner_radius = 0.1;
    expect_error(g, a, "cloth.outline.inner_radius_m", "below radius_m");
    expect_error(g, polygon({{0, 0}, {0.1, 0}}), "cloth.outline.points_m", "at least 3 points");
    expect_error(g, polygon({{0, 0}, {0.1, 0}, {0.2, 0}}), "cloth.outline.points_m", "encloses no area");
    expect_error(g, polygon({{0, 0}, {0.1, 0.1}, {0.1, 0}, {0, 0.05}}), "cloth.outline.points_m", "intersects itself (edges 0 and 2)");
    expect_error(g, polygon({{0, 0}, {0.1, 0}, {0.1, 0}, {0, 0.1}}), "cloth.outline.points_m", "repeats the next one");
    expect_error(g, disc(0.16), "cloth.outline", "reaches beyond the grid's particles");
    // Between four particles, smaller than their spacing: no particle inside.
    expect_error(g, disc(0.004, {0.005, 0.005}), "cloth.outline", "encloses no particle");
    // Round one particle only: it has no thread neighbour.
    expect_error(g, disc(0.006), "cloth.outline", "too small for the grid");
    // A thin strip one particle wide: particles in a line, no complete cell.
    expect_error(g, polygon({{-0.1, -0.003}, {0.1, -0.003}, {0.1, 0.003}, {-0.1, 0.003}}), "cloth.outline", "no grid cell");
}

TEST(Outline, ClothMassIsWTimesTheOutlinesArea)
{
    // A 30 cm specimen disc at 0.5 cm: the model's masses sum to W pi R^2; the stencils keep
    // only terms whose particles are all inside; gravity acts on the kept particles only.
    woven::kes::FabricData f;
    f.name = "t";
    f.source = "t";
    f.areal_density_mg_cm2 = 12.0;  // 0.12 kg/m^2
    f.bending_warp.summary = woven::kes::BendingSummary{0.1, 0.05};
    f.bending_weft.summary = woven::kes::BendingSummary{0.1, 0.05};
    f.shear.summary = woven::kes::ShearSummary{1.0, 1.0, 2.0};
    f.bending_warp.curve = woven::kes::synthesize_bending_curve(*f.bending_warp.summary);
    f.bending_weft.curve = woven::kes::synthesize_bending_curve(*f.bending_weft.summary);
    f.shear.curve = woven::kes::synthesize_shear_curve(*f.shear.summary);
    const m::Grid g = grid(63, 63, 0.005);
    const m::ClothCut c = m::cut_grid(g, disc(0.15), "s", "f");
    const m::ClothModel model = m::make_cloth_model(f, g, m::ModelOptions{}, c.active, c.area);
    double mass = 0;
    for (int p = 0; p < g.size(); ++p) mass += model.mass(p);
    EXPECT_NEAR(mass, 0.12 * kPi * 0.15 * 0.15, 1e-12);
    for (const auto& e : model.stencils().edges) EXPECT_TRUE(c.active[e[0]] && c.active[e[1]]);
    for (const auto& b : model.stencils().warp_bends) EXPECT_TRUE(c.active[b[0]] && c.active[b[1]] && c.active[b[2]]);
    EXPECT_EQ(static_cast<int>(model.stencils().particles.size()), c.count);
    // Without areas, in the paper's convention every kept particle weighs a full patch: the
    // disc would weigh more.
    m::ModelOptions paper;
    paper.discretization = m::Discretization::PAPER;
    const m::ClothModel patches = m::make_cloth_model(f, g, paper, c.active);
    double patch_mass = 0;
    for (int p = 0; p < g.size(); ++p) patch_mass += patches.mass(p);
    EXPECT_NEAR(patch_mass, 0.12 * c.count * 0.005 * 0.005, 1e-12);
}

namespace {

/// Edges used by exactly one face, and by more than two.
std::pair<int, int> open_and_overused_edges(const woven::geometry::TriangleMesh& mesh)
{
    std::map<std::pair<int, int>, int> uses;
    for (const auto& f : mesh.faces)
        for (int k = 0; k < 3; ++k) ++uses[std::minmax(f[k], f[(k + 1) % 3])];
    int open = 0, over = 0;
    for (const auto& [e, n] : uses) {
        open += n == 1;
        over += n > 2;
    }
    return {open, over};
}

}  // namespace

// Issue 53 item 9: the cut surface (cusick.obj, a cut cloth's drape.obj) was a triangle soup at
// its rim: every clipped cell's triangles had their own vertices (silk at 0.5 cm: 8,932 vertices
// at 4,601 positions, 6,355 open edges), which breaks smoothing, normals and curvature in mesh
// readers. Welded, its only open edges are the cut edge's, one loop, each vertex once.
TEST(Outline, TheCutSurfaceIsWeldedItsOnlyOpenEdgesTheOutline)
{
    for (const auto& [R, s, n] : {std::tuple{0.15, 0.005, 65}, std::tuple{0.06, 0.01, 15}, std::tuple{0.1234, 0.007, 39}}) {
        const m::Grid g = grid(n, n, s);
        const m::ClothCut c = m::cut_grid(g, disc(R), "s", "f");
        Positions x = flat(g);
        for (auto& p : x) p.z() = 0.2 + 0.3 * p.x() * p.x();  // not flat: the bilinear map matters
        std::vector<Vec2> uv;
        const auto mesh = m::cut_surface(g, c, x, &uv);
        const auto [open, over] = open_and_overused_edges(mesh);
        EXPECT_EQ(over, 0) << R;
        // The open edges are the outline's: their vertices at rest radius R, as many as edges
        // (one loop), and the surface a disc: V - E + F = 1.
        std::set<int> rim;
        std::map<std::pair<int, int>, int> uses;
        for (const auto& f : mesh.faces)
            for (int k = 0; k < 3; ++k) ++uses[std::minmax(f[k], f[(k + 1) % 3])];
        for (const auto& [e, u] : uses)
            if (u == 1) {
                rim.insert(e.first);
                rim.insert(e.second);
                EXPECT_NEAR(uv[e.first].norm() * s, R, 1e-5 * R) << R;  // on the outline's 720-gon
            }
        EXPECT_EQ(static_cast<int>(rim.size()), open) << R;
        EXPECT_EQ(static_cast<int>(mesh.vertices.size()) - static_cast<int>(uses.size()) + static_cast<int>(mesh.faces.size()), 1) << R;
        // One vertex per particle kept, the rest on the cut edge, no two at one rest position.
        int particles = 0;
        for (char a : c.active) particles += a;
        std::set<std::pair<long, long>> at;
        for (const Vec2& t : uv) at.insert({std::lround(t.x() * 1e6), std::lround(t.y() * 1e6)});
        EXPECT_EQ(at.size(), mesh.vertices.size()) << R;
        EXPECT_GE(static_cast<int>(mesh.vertices.size()), particles) << R;  // a particle on the outline is a rim vertex too
        EXPECT_LE(static_cast<int>(mesh.vertices.size()), particles + open) << R;
        EXPECT_NEAR(mesh_area(m::cut_surface(g, c, flat(g))), kPi * R * R, 1e-9 * R * R) << R;
    }
}
