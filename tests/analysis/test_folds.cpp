// analysis / folds: sections, billows on synthetic skirts with known folds, drape measures.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "woven/analysis/folds.hpp"
#include "woven/common/error.hpp"
#include "woven/geometry/mesh_ops.hpp"

using namespace woven;
using analysis::Billow;
using analysis::BoxFootprint;
using analysis::Section;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180;

/// Billows wanted at one corner: angles from its diagonal (degrees, counter-clockwise).
struct CornerSpec {
    std::vector<double> angles_deg;
};

constexpr double kBase = 0.03;       // m: the skirt's distance from the footprint away from the billows
constexpr double kAmplitude = 0.05;  // m: a billow's rise above it
constexpr double kHalfWidth = 12;    // degrees: half width of a billow (raised cosine)

/// The footprint distance in direction phi (degrees, absolute) around a corner whose diagonal
/// points at diag_deg.
double corner_profile(const CornerSpec& spec, double diag_deg, double phi_deg, double ripple)
{
    double r = kBase;
    for (double a : spec.angles_deg) {
        double rel = phi_deg - diag_deg - a;
        rel -= 360 * std::round(rel / 360);
        const double t = rel / kHalfWidth;
        if (std::abs(t) < 1) r += kAmplitude * std::pow(std::cos(0.5 * kPi * t), 2);
    }
    return r + ripple * std::sin(phi_deg * kDeg * 40);  // a small ripple (period 9 degrees), below the prominence
}

double angle_deg(const Vec2& v) { return std::atan2(v.y(), v.x()) / kDeg; }

/// A closed section around the footprint: at each corner an arc over the corner's normal cone
/// (from one side's normal to the next) whose distance from the footprint is corner_profile (a
/// point in the cone is exactly that far from the rectangle), straight sides at kBase in
/// between; 0.5 degree steps. Starts at corner `start_corner`'s direction `start_deg` from its
/// diagonal, so a billow there straddles the start.
std::vector<Vec2> ring(const BoxFootprint& box, const std::vector<CornerSpec>& corners, int start_corner, double start_deg,
                       double ripple = 0.0)
{
    std::vector<Vec2> pts;
    int start = 0;
    for (int c = 0; c < 4; ++c) {
        const Vec2 corner = box.corner(c);
        const double diag = angle_deg(box.diagonal(c));
        const double first = box.yaw_rad / kDeg + 90.0 * c;  // normal of the side before the corner
        if (c == start_corner) {
            double rel = diag + start_deg - first;
            rel -= 360 * std::floor(rel / 360);
            start = static_cast<int>(pts.size()) + static_cast<int>(std::lround(rel / 0.5));
        }
        for (int k = 0; k < 180; ++k) {
            const double phi = first + 0.5 * k;
            pts.push_back(corner + corner_profile(corners[c], diag, phi, ripple) * Vec2(std::cos(phi * kDeg), std::sin(phi * kDeg)));
        }
        const Vec2 next = box.corner((c + 1) % 4);
        const Vec2 normal(std::cos((first + 90) * kDeg), std::sin((first + 90) * kDeg));
        for (int k = 0; k < 20; ++k) pts.push_back(corner + (next - corner) * (k / 20.0) + kBase * normal);
    }
    std::rotate(pts.begin(), pts.begin() + start, pts.end());
    return pts;
}

/// A vertical skirt: the ring repeated at heights from top_z down to top_z - 0.3 m, quads split
/// in two. Its first face starts at the ring's first point.
geometry::TriangleMesh skirt(const std::vector<Vec2>& r, double top_z)
{
    geometry::TriangleMesh m;
    const int n = static_cast<int>(r.size()), rows = 7;
    for (int k = 0; k < rows; ++k)
        for (const Vec2& p : r) m.vertices.emplace_back(p.x(), p.y(), top_z - 0.3 * k / (rows - 1));
    for (int k = 0; k + 1 < rows; ++k)
        for (int i = 0; i < n; ++i) {
            const int a = k * n + i, b = k * n + (i + 1) % n, c = b + n, d = a + n;
            m.faces.emplace_back(a, b, c);
            m.faces.emplace_back(a, c, d);
        }
    return m;
}

Section loop_of(const std::vector<Vec2>& r, double z = 0.4)
{
    Section s;
    for (const Vec2& p : r) s.points.emplace_back(p.x(), p.y(), z);
    s.closed = true;
    return s;
}

/// Checks one corner's billows against the spec: the same count, angles within tol degrees,
/// stand-out kBase + kAmplitude within 1 mm.
void expect_corner(const std::vector<Billow>& all, int c, const CornerSpec& spec, double tol_deg)
{
    std::vector<Billow> got;
    for (const Billow& b : all)
        if (b.corner == c) got.push_back(b);
    ASSERT_EQ(got.size(), spec.angles_deg.size()) << "corner " << c;
    std::vector<double> want = spec.angles_deg;
    std::sort(want.begin(), want.end());
    for (std::size_t k = 0; k < want.size(); ++k) {
        EXPECT_NEAR(got[k].angle_deg, want[k], tol_deg) << "corner " << c << " billow " << k;
        EXPECT_NEAR(got[k].standout_m, kBase + kAmplitude, 1.5e-3) << "corner " << c;
        EXPECT_GE(got[k].prominence_m, 0.01);
    }
}

BoxFootprint cube_footprint()
{
    BoxFootprint box;
    box.centre = Vec2::Zero();
    box.half = Vec2(0.25, 0.25);
    box.top_z = 0.5;
    return box;
}

}  // namespace

TEST(Footprint, DistanceCornersAndQuadrants)
{
    BoxFootprint box;
    box.centre = Vec2(0.1, -0.2);
    box.half = Vec2(0.3, 0.2);
    box.yaw_rad = 0.3;
    EXPECT_NEAR(box.distance(box.to_world(Vec2(0.5, 0))), 0.2, 1e-12);
    EXPECT_NEAR(box.distance(box.to_world(Vec2(0.6, 0.6))), std::hypot(0.3, 0.4), 1e-12);
    EXPECT_NEAR(box.distance(box.to_world(Vec2(0.0, 0.1))), -0.1, 1e-12);
    for (int c = 0; c < 4; ++c) {
        EXPECT_NEAR(box.distance(box.corner(c)), 0.0, 1e-12);
        EXPECT_EQ(box.quadrant(box.corner(c) + 0.01 * box.diagonal(c)), c);
        EXPECT_NEAR((box.corner(c) - box.centre).normalized().dot(box.diagonal(c)), 1.0, 1e-12);
    }
    EXPECT_NEAR(box.to_local(box.to_world(Vec2(0.3, -0.7))).x(), 0.3, 1e-12);
}

// One billow per corner on the diagonal (the paper's cotton), the loop starting on the top of
// corner 0's billow: exactly one billow there, not two halves, at 0 degrees.
TEST(Billows, OnePerCornerAtDiagonalStraddlingTheStart)
{
    const BoxFootprint box = cube_footprint();
    const std::vector<CornerSpec> spec(4, CornerSpec{{0.0}});
    const auto billows = analysis::find_billows(loop_of(ring(box, spec, 0, 0.0)), box, 0.01);
    ASSERT_EQ(billows.size(), 4u);
    for (int c = 0; c < 4; ++c) expect_corner(billows, c, spec[c], 0.3);
}

// Different structures at each corner (two folds, an asymmetric billow, three folds, one on
// the diagonal); the answer must not depend on where the loop starts: every start is tried,
// including the top and the flanks of each billow.
TEST(Billows, KnownFoldsAtKnownAnglesForEveryStart)
{
    const BoxFootprint box = cube_footprint();
    const std::vector<CornerSpec> spec = {{{-20.0, 20.0}}, {{25.0}}, {{-28.0, 0.0, 28.0}}, {{-33.0}}};
    const Section base = loop_of(ring(box, spec, 0, -45.0, 0.001));
    const int n = static_cast<int>(base.points.size());
    for (int start = 0; start < n; ++start) {
        Section s = base;
        std::rotate(s.points.begin(), s.points.begin() + start, s.points.end());
        const auto billows = analysis::find_billows(s, box, 0.01);
        ASSERT_EQ(billows.size(), 7u) << "start " << start;
        for (int c = 0; c < 4; ++c) expect_corner(billows, c, spec[c], 1.0);
    }
}

// An open arc (the same curve cut at a billow's top): each end is an end, not a billow.
TEST(Billows, OpenArcEndsAreNotBillows)
{
    const BoxFootprint box = cube_footprint();
    const std::vector<CornerSpec> spec(4, CornerSpec{{0.0}});
    Section s = loop_of(ring(box, spec, 1, 0.0));
    s.closed = false;
    const auto billows = analysis::find_billows(s, box, 0.01);
    ASSERT_EQ(billows.size(), 3u);
    for (const Billow& b : billows) EXPECT_NE(b.corner, 1);
}

// A rotated, off-centre, rectangular box: angles are measured in its frame.
TEST(Billows, RotatedRectangularBox)
{
    BoxFootprint box;
    box.centre = Vec2(0.3, -0.1);
    box.half = Vec2(0.35, 0.2);
    box.yaw_rad = 0.4;
    box.top_z = 0.7;
    const std::vector<CornerSpec> spec = {{{10.0}}, {{-15.0, 15.0}}, {{0.0}}, {{-30.0}}};
    const auto billows = analysis::find_billows(loop_of(ring(box, spec, 3, -30.0), 0.6), box, 0.01);
    ASSERT_EQ(billows.size(), 5u);
    for (int c = 0; c < 4; ++c) expect_corner(billows, c, spec[c], 1.0);
}

// The whole pipeline on a mesh: slicing a vertical skirt at 0.1 and 0.2 m below the top gives
// closed loops around the box, and the billows built into it, whichever face comes first.
TEST(FoldAnalysis, SkirtMeshSectionsFindTheBuiltInFolds)
{
    const BoxFootprint box = cube_footprint();
    const std::vector<CornerSpec> spec = {{{0.0}}, {{-22.0, 22.0}}, {{30.0}}, {{-25.0, 0.0, 25.0}}};
    for (double start_deg : {0.0, -22.0, 30.0}) {
        const int start_corner = start_deg == 0.0 ? 0 : start_deg < 0 ? 1 : 2;
        const geometry::TriangleMesh mesh = skirt(ring(box, spec, start_corner, start_deg), box.top_z);
        const analysis::FoldAnalysis fa = analysis::analyse_folds(mesh, box);
        ASSERT_EQ(fa.sections.size(), 2u);
        for (const auto& sf : fa.sections) {
            EXPECT_TRUE(sf.found);
            EXPECT_TRUE(sf.closed);
            EXPECT_GT(sf.length_m, 4 * 0.5);
            for (int c = 0; c < 4; ++c) expect_corner(sf.billows, c, spec[c], 1.0);
        }
        EXPECT_NEAR(fa.sections[0].height_m, 0.4, 1e-12);
        EXPECT_NEAR(fa.sections[1].height_m, 0.3, 1e-12);
        EXPECT_NEAR(fa.lowest_point.z(), 0.2, 1e-12);
        for (double h : fa.hanging_m) EXPECT_NEAR(h, 0.3, 1e-12);
    }
}

TEST(Slice, CylinderGivesOneClosedLoopOfItsCircumference)
{
    geometry::TriangleMesh m;
    const int n = 200;
    const double r = 0.3;
    for (int k = 0; k < 2; ++k)
        for (int i = 0; i < n; ++i)
            m.vertices.emplace_back(r * std::cos(2 * kPi * i / n), r * std::sin(2 * kPi * i / n), k == 0 ? 0.0 : 1.0);
    for (int i = 0; i < n; ++i) {
        m.faces.emplace_back(i, (i + 1) % n, n + (i + 1) % n);
        m.faces.emplace_back(i, n + (i + 1) % n, n + i);
    }
    const auto sections = analysis::slice(m, 0.37);
    ASSERT_EQ(sections.size(), 1u);
    EXPECT_TRUE(sections[0].closed);
    EXPECT_EQ(sections[0].points.size(), static_cast<std::size_t>(2 * n));
    double len = 0;
    const auto& p = sections[0].points;
    for (std::size_t i = 0; i < p.size(); ++i) len += (p[(i + 1) % p.size()] - p[i]).norm();
    EXPECT_NEAR(len, 2 * n * r * std::sin(kPi / n), 1e-9);  // the inscribed polygon
    for (const Vec3& q : p) EXPECT_DOUBLE_EQ(q.z(), 0.37);
}

TEST(Slice, TiltedSheetGivesOneOpenArcAcrossIt)
{
    // A 1 m x 1 m grid rising along y: z = 0.5 y; the plane z = 0.2 cuts it along y = 0.4.
    Positions x;
    const int nu = 11, nv = 11;
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) x.emplace_back(0.1 * i, 0.1 * j, 0.05 * j);
    const auto sections = analysis::slice(geometry::grid_mesh(x, nu, nv), 0.2);
    ASSERT_EQ(sections.size(), 1u);
    EXPECT_FALSE(sections[0].closed);
    const auto& p = sections[0].points;
    EXPECT_NEAR((p.front() - p.back()).norm(), 1.0, 1e-12);
    for (const Vec3& q : p) EXPECT_NEAR(q.y(), 0.4, 1e-12);
}

TEST(ProjectedArea, SquareTriangleAndOverlapCountedOnce)
{
    Positions x;
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) x.emplace_back(-0.5 + 0.5 * i, -0.5 + 0.5 * j, 0.1 * i * j);
    geometry::TriangleMesh sq = geometry::grid_mesh(x, 3, 3);
    EXPECT_NEAR(analysis::projected_area(sq), 1.0, 0.005);  // 1 mm cells on a 4 m perimeter
    geometry::TriangleMesh twice = sq;
    for (const auto& f : sq.faces) twice.faces.emplace_back(f[0], f[2], f[1]);  // reversed copies
    EXPECT_NEAR(analysis::projected_area(twice), analysis::projected_area(sq), 1e-12);
    geometry::TriangleMesh tri;
    tri.vertices = {Vec3(0, 0, 0), Vec3(0.4, 0, 1), Vec3(0, 0.3, -2)};
    tri.faces = {Eigen::Vector3i(0, 1, 2)};
    EXPECT_NEAR(analysis::projected_area(tri), 0.06, 0.06 * 0.02);
}

TEST(FoldAnalysis, RejectsBadOptions)
{
    const BoxFootprint box = cube_footprint();
    const geometry::TriangleMesh mesh = skirt(ring(box, std::vector<CornerSpec>(4), 0, 0.0), 0.5);
    analysis::FoldOptions o;
    o.depths_m = {0.1, -0.2};
    EXPECT_THROW(analysis::analyse_folds(mesh, box, o), InputError);
    o = {};
    o.prominence_m = 0;
    EXPECT_THROW(analysis::analyse_folds(mesh, box, o), InputError);
    BoxFootprint flat = box;
    flat.half.y() = 0;
    EXPECT_THROW(analysis::analyse_folds(mesh, flat), InputError);
    EXPECT_THROW(analysis::analyse_folds(geometry::TriangleMesh{}, box), InputError);
    EXPECT_THROW(geometry::grid_mesh(Positions(5), 2, 3), InputError);
}

// No folds: a plain skirt has no billow at any corner, and the section still closes.
TEST(FoldAnalysis, PlainSkirtHasNoBillows)
{
    const BoxFootprint box = cube_footprint();
    const geometry::TriangleMesh mesh = skirt(ring(box, std::vector<CornerSpec>(4), 2, 10.0, 0.001), 0.5);
    const analysis::FoldAnalysis fa = analysis::analyse_folds(mesh, box);
    for (const auto& sf : fa.sections) {
        EXPECT_TRUE(sf.closed);
        EXPECT_TRUE(sf.billows.empty());
    }
}

// The corner structures of the paper's Sec. 6: one billow on the diagonal (cotton), two folds
// (wool), a billow pushed round the corner (polyester/cotton); the asymmetry weights by standout.
TEST(CornerStructure, ClassifiesTheBillowsOfACorner)
{
    auto billow = [](double angle, double standout) {
        Billow b;
        b.angle_deg = angle;
        b.standout_m = standout;
        return b;
    };
    using analysis::CornerStructure;
    EXPECT_EQ(analysis::corner_structure({}), CornerStructure::NONE);
    EXPECT_EQ(analysis::corner_structure({billow(-14.9, 0.1)}), CornerStructure::SINGLE_BILLOW);
    EXPECT_EQ(analysis::corner_structure({billow(15.1, 0.1)}), CornerStructure::PUSHED_BILLOW);
    EXPECT_EQ(analysis::corner_structure({billow(-20, 0.1), billow(20, 0.1)}), CornerStructure::TWO_FOLDS);
    EXPECT_EQ(analysis::corner_structure({billow(-30, 0.1), billow(0, 0.1), billow(30, 0.1)}), CornerStructure::SEVERAL_FOLDS);
    // A side-panel wave (beyond the 80-degree cone) and a ripple on the main billow's flank
    // (below half its standout) are not folds: the paper solver's cotton corner, one billow at
    // +41 degrees standing out 0.06 m with a 0.013 m wave of the side at -130 degrees, is one
    // billow pushed round the corner, not two folds.
    EXPECT_EQ(analysis::corner_structure({billow(41, 0.06), billow(-130, 0.013)}), CornerStructure::PUSHED_BILLOW);
    EXPECT_EQ(analysis::corner_structure({billow(-5, 0.06), billow(40, 0.029)}), CornerStructure::SINGLE_BILLOW);
    EXPECT_EQ(analysis::corner_structure({billow(-5, 0.06), billow(40, 0.03)}), CornerStructure::TWO_FOLDS);
    EXPECT_EQ(analysis::corner_structure({billow(-90.5, 0.2), billow(60, 0.01)}), CornerStructure::PUSHED_BILLOW);
    // Two folds of the fast solver's cotton (seed 3): one at -84 degrees, in front of the side
    // near the corner, as large as its partner at +53.
    EXPECT_EQ(analysis::corner_structure({billow(-84, 0.065), billow(53, 0.062)}), CornerStructure::TWO_FOLDS);
    const analysis::CornerBillows split = analysis::split_corner_billows({billow(-60, 0.05), billow(10, 0.02), billow(50, 0.04), billow(120, 0.08)});
    ASSERT_EQ(split.folds.size(), 2u);
    EXPECT_EQ(split.folds[0].angle_deg, -60);
    EXPECT_EQ(split.folds[1].angle_deg, 50);
    ASSERT_EQ(split.ripples.size(), 1u);
    EXPECT_EQ(split.ripples[0].angle_deg, 10);
    ASSERT_EQ(split.side_waves.size(), 1u);
    EXPECT_EQ(split.side_waves[0].angle_deg, 120);
    EXPECT_STREQ(analysis::to_string(CornerStructure::SINGLE_BILLOW), "single billow");
    EXPECT_DOUBLE_EQ(analysis::corner_asymmetry_deg({}), 0.0);
    EXPECT_DOUBLE_EQ(analysis::corner_asymmetry_deg({billow(-20, 0.1), billow(20, 0.1)}), 0.0);
    EXPECT_NEAR(analysis::corner_asymmetry_deg({billow(-20, 0.05), billow(25, 0.15)}), (-20 * 0.05 + 25 * 0.15) / 0.2, 1e-12);
}
