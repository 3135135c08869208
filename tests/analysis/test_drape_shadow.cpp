// The drape tester's measures: shadow area (exact references), drape coefficient, and the node
// counter on synthetic shadows with k lobes, including a lobe that straddles angle 0.
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "woven/analysis/drape_shadow.hpp"
#include "woven/common/error.hpp"

namespace an = woven::analysis;
using woven::Vec2;
using woven::Vec3;
using woven::geometry::TriangleMesh;

namespace {

constexpr double kPi = std::numbers::pi;

/// A star-shaped polygon r(theta) (theta from +y towards +x), as a triangle fan around `centre`
/// at height z; n vertices.
template <class F> TriangleMesh star(F r, int n, const Vec2& centre = Vec2::Zero(), double z = 0.2)
{
    TriangleMesh m;
    m.vertices.push_back(Vec3(centre.x(), centre.y(), z));
    for (int k = 0; k < n; ++k) {
        const double th = 2 * kPi * k / n;
        m.vertices.push_back(Vec3(centre.x() + r(th) * std::sin(th), centre.y() + r(th) * std::cos(th), z));
    }
    for (int k = 0; k < n; ++k) m.faces.emplace_back(0, 1 + k, 1 + (k + 1) % n);
    return m;
}

/// Exact area of a star polygon's fan.
template <class F> double star_area(F r, int n)
{
    double a = 0;
    for (int k = 0; k < n; ++k) a += 0.5 * r(2 * kPi * k / n) * r(2 * kPi * (k + 1) / n) * std::sin(2 * kPi / n);
    return a;
}

}  // namespace

TEST(DrapeShadow, AreaOfOneTriangleAndOfOverlappingSquaresIsExact)
{
    TriangleMesh t;
    t.vertices = {Vec3(0, 0, 0), Vec3(0.3, 0.05, 0.1), Vec3(0.1, 0.2, -0.1)};
    t.faces = {Eigen::Vector3i(0, 1, 2)};
    const double exact = 0.5 * std::abs(0.3 * 0.2 - 0.05 * 0.1);
    EXPECT_NEAR(an::shadow_area(t), exact, 1e-8);  // x-sections linear in y: the midpoint rule errs only in the rows at the vertices

    // Two unit squares overlapping in a 0.5 x 1 strip, and the first one twice (the union counts it once).
    TriangleMesh s;
    auto square = [&](double x0, double z) {
        const int b = static_cast<int>(s.vertices.size());
        s.vertices.insert(s.vertices.end(), {Vec3(x0, 0, z), Vec3(x0 + 1, 0, z), Vec3(x0 + 1, 1, z), Vec3(x0, 1, z)});
        s.faces.emplace_back(b, b + 1, b + 2);
        s.faces.emplace_back(b, b + 2, b + 3);
    };
    square(0.0, 0.0);
    square(0.5, 0.3);
    square(0.0, -0.2);
    EXPECT_NEAR(an::shadow_area(s, 1e-3), 1.5, 1e-9);
}

TEST(DrapeShadow, AreaOfAPolygonConvergesAtSecondOrder)
{
    auto r = [](double th) { return 0.12 + 0.03 * std::cos(5 * th); };
    const TriangleMesh m = star(r, 400);
    const double exact = star_area(r, 400);
    const double e1 = std::abs(an::shadow_area(m, 1e-3) - exact);
    const double e2 = std::abs(an::shadow_area(m, 1e-4) - exact);
    EXPECT_LT(e2 / exact, 1e-5);  // the header's "about 2e-6 relative at 0.1 mm", with margin
    EXPECT_LT(e2, e1 / 10 + 1e-12);
}

TEST(DrapeShadow, FlatUndrapedSpecimenHasDC100)
{
    // A 30 cm specimen as a 720-gon with the circle's exact area, on an 18 cm disc.
    const double R = 0.15, rd = 0.09;
    const int n = 720;
    const double Rp = R * std::sqrt(2 * kPi / (n * std::sin(2 * kPi / n)));
    const TriangleMesh flat = star([&](double) { return Rp; }, n);
    const double A = kPi * R * R;
    EXPECT_NEAR(an::shadow_area(flat), A, 1e-5 * A);
    const an::DrapeShadow d = an::measure_drape(flat, Vec2::Zero(), rd, R, A);
    EXPECT_NEAR(d.drape_coefficient_percent, 100.0, 1e-3);
    EXPECT_EQ(d.nodes.count(), 0);
    for (double r : d.radius_m) EXPECT_NEAR(r, R, 2e-5);
}

TEST(DrapeShadow, DCOfAShadowTheSizeOfTheDiscIsZero)
{
    const double rd = 0.09;
    const int n = 720;
    const double Rp = rd * std::sqrt(2 * kPi / (n * std::sin(2 * kPi / n)));
    const TriangleMesh m = star([&](double) { return Rp; }, n);
    EXPECT_NEAR(an::measure_drape(m, Vec2::Zero(), rd, 0.15, kPi * 0.15 * 0.15).drape_coefficient_percent, 0.0, 1e-3);
    // Half way in area: DC 50 %.
    const double Rh = std::sqrt(0.5 * (0.15 * 0.15 + rd * rd)) * std::sqrt(2 * kPi / (n * std::sin(2 * kPi / n)));
    const TriangleMesh h = star([&](double) { return Rh; }, n);
    EXPECT_NEAR(an::measure_drape(h, Vec2::Zero(), rd, 0.15, kPi * 0.15 * 0.15).drape_coefficient_percent, 50.0, 1e-3);
}

TEST(DrapeShadow, ShadowRadiusOfAnOffCentreStarIsItsOutline)
{
    const Vec2 c(0.4, -0.2);
    auto r = [](double th) { return 0.13 + 0.02 * std::cos(6 * th + 0.3); };
    const TriangleMesh m = star(r, 1440, c);
    const std::vector<double> rr = an::shadow_radius(m, c, 1440);
    for (int k = 0; k < 1440; ++k) EXPECT_NEAR(rr[k], r(2 * kPi * k / 1440), 1e-9) << k;
}

struct Lobes {
    int k;
    double phase_deg;  ///< angle of the first lobe's tip
};

class NodeCounter : public ::testing::TestWithParam<Lobes> {};

TEST_P(NodeCounter, FindsExactlyKNodesOnAKLobedShadow)
{
    const Lobes p = GetParam();
    const double R = 0.15, rd = 0.09, amp = 0.02, phase = p.phase_deg * kPi / 180;
    for (const double ripple : {0.0, 0.0006}) {
        SCOPED_TRACE(ripple);
        // Lobes of a draped specimen; the second time with a small ripple (a tenth of the
        // 6 mm prominence threshold) as a coarse grid's faceting would add.
        auto r = [&](double th) { return 0.125 + amp * std::cos(p.k * (th - phase)) + ripple * std::cos(37 * th); };
        const TriangleMesh m = star(r, 2880);
        // measure_drape's threshold: a tenth of the overhang.
        const an::Nodes nodes = an::find_nodes(an::shadow_radius(m, Vec2::Zero()), R, 0.1 * (R - rd));
        ASSERT_EQ(nodes.count(), p.k);
        for (int j = 0; j < p.k; ++j) {
            EXPECT_NEAR(nodes.radius_m[j], 0.145, 0.001);
            EXPECT_NEAR(nodes.depth_m[j], R - nodes.radius_m[j], 1e-12);
            EXPECT_NEAR(nodes.amplitude_m[j], 2 * amp, 0.002);
            if (j > 0) {
                EXPECT_LT(nodes.angle_deg[j - 1], nodes.angle_deg[j]);
            }
        }
        if (ripple > 0) continue;  // the ripple moves the tips; their places are checked without it
        for (int j = 0; j < p.k; ++j) {
            const double expect = std::fmod(p.phase_deg + 360.0 * j / p.k, 360.0);
            double best = 360;
            for (double a : nodes.angle_deg) best = std::min(best, std::abs(std::remainder(a - expect, 360.0)));
            EXPECT_LT(best, 0.05) << "lobe " << j << " at " << expect;
        }
    }
}

INSTANTIATE_TEST_SUITE_P(DrapeShadow, NodeCounter,
                         ::testing::Values(Lobes{1, 90}, Lobes{2, 10}, Lobes{3, 0}, Lobes{4, 45}, Lobes{5, 359.9}, Lobes{6, 0.1},
                                           Lobes{7, 3}, Lobes{8, 22.5}, Lobes{9, 180}, Lobes{10, 0}, Lobes{12, 357}));

TEST(DrapeShadow, PeriodicPeaksHandleWrapPlateausAndThreshold)
{
    // A plateau spanning the end and the start is one peak, at its middle (index 0).
    std::vector<double> v = {5, 5, 1, 0, 1, 2, 1, 0, 1, 5};
    auto p = an::periodic_peaks(v, 0.5);
    ASSERT_EQ(p.size(), 2u);
    EXPECT_NEAR(p[0].index, 0.0, 1e-12);
    EXPECT_DOUBLE_EQ(p[0].value, 5);
    EXPECT_DOUBLE_EQ(p[0].prominence, 5);
    EXPECT_NEAR(p[1].index, 5.0, 1e-12);
    EXPECT_DOUBLE_EQ(p[1].prominence, 2);
    // The small peak falls below a threshold of 3.
    EXPECT_EQ(an::periodic_peaks(v, 3.0).size(), 1u);
    // A constant sequence, and a sequence with one minimum, have no / one peak.
    EXPECT_TRUE(an::periodic_peaks(std::vector<double>(50, 0.1), 1e-6).empty());
    EXPECT_EQ(an::periodic_peaks({0, 1, 2, 3, 2, 1}, 1.0).size(), 1u);
    // Two equal tops both count (neither is higher ground for the other).
    EXPECT_EQ(an::periodic_peaks({0, 2, 0, 2}, 1.5).size(), 2u);
    EXPECT_THROW(an::periodic_peaks(v, 0.0), woven::InputError);
    EXPECT_THROW(an::periodic_peaks({1, 2}, 1.0), woven::InputError);
}

TEST(DrapeShadow, RasterAgreesWithTheAreaToAPixelRing)
{
    auto r = [](double th) { return 0.12 + 0.025 * std::cos(7 * th); };
    const TriangleMesh m = star(r, 1000);
    const double exact = star_area(r, 1000);
    const double px = 5e-4;
    const an::ShadowRaster s = an::rasterize_shadow(m, Vec2(-0.2, -0.2), px, 800, 800);
    // Counting pixel centres errs by at most the boundary's length times half a pixel diagonal.
    const double perimeter = 1.2;
    EXPECT_NEAR(s.area_m2(), exact, perimeter * px * 0.71);
    EXPECT_NEAR(s.area_m2(), exact, 0.002 * exact);
    EXPECT_EQ(s.covered[400 + 800 * 400], 1);  // the centre
    EXPECT_EQ(s.covered[0], 0);                // a corner
}

TEST(DrapeShadow, BadInputsThrow)
{
    EXPECT_THROW(an::drape_coefficient_percent(0.05, 0.0, 0.07), woven::InputError);
    EXPECT_THROW(an::drape_coefficient_percent(0.05, 0.07, 0.07), woven::InputError);
    TriangleMesh m;
    EXPECT_THROW(an::shadow_area(m, 0.0), woven::InputError);
    EXPECT_EQ(an::shadow_area(m), 0.0);
    EXPECT_THROW(an::shadow_radius(m, Vec2::Zero(), 4), woven::InputError);
    EXPECT_THROW(an::measure_drape(m, Vec2::Zero(), 0.15, 0.09, 0.07), woven::InputError);
    // Non-finite vertices are skipped, not propagated.
    m.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, NAN, 0)};
    m.faces = {Eigen::Vector3i(0, 1, 2)};
    EXPECT_EQ(an::shadow_area(m), 0.0);
}

// Issue 53: one particle far away (a start file's) sized the scanline table by the extent over
// the row: 1 km made 9.3 GB, 1000 km threw "cannot create std::vector larger than max_size()".
// Now the rows are capped (kMaxShadowRows, kMaxShadowRowSpans) and swept: O(faces) memory.
TEST(DrapeShadow, AParticleFarAwayNeitherTakesTheMachineNorThrows)
{
    auto r = [](double th) { return 0.15 + 0.0 * th; };
    for (const double far_m : {1e3, 1e6, 1e12}) {
        TriangleMesh m = star(r, 720);
        const double disc = star_area(r, 720);
        // A sliver from the rim to the far particle: 1 mm wide, far_m long.
        const int a = static_cast<int>(m.vertices.size());
        m.vertices.push_back(Vec3(0, 0.15, 0.2));
        m.vertices.push_back(Vec3(1e-3, 0.15, 0.2));
        m.vertices.push_back(Vec3(0, far_m, 0.2));
        m.faces.emplace_back(a, a + 1, a + 2);
        const double row = an::shadow_row_m(m);
        EXPECT_LE((far_m + 0.15) / row, static_cast<double>(an::kMaxShadowRows) + 1) << far_m;
        const double area = an::shadow_area(m);
        // The disc (its rows are now far wider than 0.1 mm: within a row's height of the rim)
        // plus the sliver's 0.5 mm x far_m.
        EXPECT_NEAR(area, disc + 0.5e-3 * far_m, 0.3 * 2 * row + 1e-3 * (disc + 0.5e-3 * far_m)) << far_m;
        EXPECT_LT(an::shadow_memory_bytes(m), 100'000u);
        const an::ShadowRaster s = an::rasterize_shadow(m, Vec2(-0.2, -0.2), 5e-4, 800, 800);
        EXPECT_NEAR(s.area_m2(), disc + 1e-3 * 0.05, 0.002 * disc) << far_m;  // the picture holds the sliver's first 5 cm
        const std::vector<double> rad = an::shadow_radius(m, Vec2::Zero(), 1440);
        EXPECT_NEAR(rad[0], far_m, 1e-6 * far_m);
        EXPECT_NEAR(rad[720], 0.15, 1e-3);
    }
    // The default 0.1 mm spacing is kept for a standard specimen.
    EXPECT_EQ(an::shadow_row_m(star(r, 720)), 1e-4);
}

// Smaller caps (fuzz/fuzz_shadow.cpp's: each input must be quick) widen the rows sooner and keep
// the area within a row's accuracy; the defaults are the documented ones.
TEST(DrapeShadow, SmallerCapsWidenTheRowsSooner)
{
    auto r = [](double) { return 0.15; };
    TriangleMesh m = star(r, 720);
    const double disc = star_area(r, 720);
    const int a = static_cast<int>(m.vertices.size());
    m.vertices.push_back(Vec3(0, 0.15, 0.2));
    m.vertices.push_back(Vec3(1e-3, 0.15, 0.2));
    m.vertices.push_back(Vec3(0, 1e3, 0.2));
    m.faces.emplace_back(a, a + 1, a + 2);
    const an::ShadowCaps small{1 << 10, 1 << 16};
    const double row = an::shadow_row_m(m, 1e-4, small);
    EXPECT_NEAR(row, (1e3 + 0.15) / (1 << 10), 1e-9);  // the rows' cap decides: 0.98 m rows
    EXPECT_EQ(an::shadow_row_m(m), (1e3 + 0.15) / static_cast<double>(an::kMaxShadowRows));  // the defaults
    EXPECT_EQ(an::shadow_row_m(m, 1e-4, an::ShadowCaps{}), an::shadow_row_m(m));
    // The sliver's 0.5 mm x 1 km and the disc, within two rows' width of the disc's outline.
    EXPECT_NEAR(an::shadow_area(m, 1e-4, small), disc + 0.5, 2 * 0.3 * row + 1e-3 * (disc + 0.5));
    // The crossings' cap: 720 faces of the disc over 0.3 m.
    const an::ShadowCaps few_spans{an::kMaxShadowRows, 1000};
    EXPECT_GT(an::shadow_row_m(star(r, 720), 1e-4, few_spans), 1e-4);
    EXPECT_EQ(an::shadow_row_m(star(r, 720), 1e-4), 1e-4);
    EXPECT_THROW(an::shadow_area(m, 1e-4, an::ShadowCaps{0, 1}), woven::InputError);
    EXPECT_THROW(an::shadow_row_m(m, 1e-4, an::ShadowCaps{1, 0}), woven::InputError);
}

// fuzz_shadow's finding (fuzz/corpus/shadow/far-flat-triangle-row-count-overflowed.bin): a
// triangle far from the origin with no height (y = 3.79e146 at its three corners) has rows on
// a grid whose start rounded past it: the row count was -4.4e134 cast to long long (undefined).
TEST(DrapeShadow, AMeshFarFromTheOriginHasRowsFromItsLowestPoint)
{
    for (const double at : {3.7921287488073793e146, 1e30, 1e20}) {
        TriangleMesh flat;
        flat.vertices = {Vec3(at, at, 0), Vec3(2 * at, at, 0), Vec3(0, at, 0)};
        flat.faces = {Eigen::Vector3i(0, 1, 2)};
        EXPECT_EQ(an::shadow_area(flat), 0.0) << at;
        // A right triangle of legs L = 1e-6 at (its size a thousand ulps of its place) has
        // area L^2 / 2 to within a few rows' (rounded) share.
        const double L = 1e-6 * at;
        TriangleMesh t;
        t.vertices = {Vec3(at, at, 0), Vec3(at + L, at, 0), Vec3(at, at + L, 0)};
        t.faces = {Eigen::Vector3i(0, 1, 2)};
        const double area = an::shadow_area(t);
        EXPECT_NEAR(area, 0.5 * L * L, 0.02 * L * L) << at;
    }
}

TEST(DrapeShadow, ExtentsBeyondDoublesAndHugeRastersAreRefused)
{
    TriangleMesh m;
    m.vertices = {Vec3(0, -1e308, 0), Vec3(1, 1e308, 0), Vec3(0, 1e308, 0)};
    m.faces = {Eigen::Vector3i(0, 1, 2)};
    EXPECT_THROW(an::shadow_area(m), woven::InputError);
    m.vertices = {Vec3(-1e300, -1e300, 0), Vec3(1e300, 1e300, 0), Vec3(-1e300, 1e300, 0)};
    EXPECT_NO_THROW(an::shadow_area(m));  // +inf (a drape's report refuses it), no overflow on the way
    EXPECT_THROW(an::rasterize_shadow(m, Vec2::Zero(), 1e-3, 1 << 14, 1 << 14), woven::InputError);
    const an::ShadowRaster s = an::rasterize_shadow(m, Vec2(-1, 0), 1e-3, 8, 8);  // above the diagonal y = x
    EXPECT_EQ(s.covered[0], 1);
}
