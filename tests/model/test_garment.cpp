// Garments (model/seams.hpp, model/garment.hpp): the seam term's gradient and Hessian against
// central differences, alone and inside a model; pattern pieces cut from one grid (disjoint,
// turned by their grain, masses summing to W x area); edge particles by arc length; stitches
// joining two edges of different particle counts; the wrap around the body an isometry.
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "model/model_test_support.hpp"
#include "woven/common/error.hpp"
#include "woven/model/garment.hpp"
#include "woven/model/seams.hpp"

namespace woven::test {
namespace {

using model::Derivatives;
constexpr double kPi = std::numbers::pi;

// ---------------------------------------------------------------------------------------------
// The seam term.

/// Two rectangles, a (6.1 x 8.1 cm) and b (6.1 cm x height_b), on a 10 cm cylinder, a's right
/// side sewn to b's left; b cut at grain_b.
model::Pattern two_panels(double grain_b = 0.0, double height_b = 0.101);

TEST(SeamTerm, GradientAndHessianMatchCentralDifferences)
{
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-0.02, 0.02);
    for (double w : {0.0, 0.3, 1.0}) {
        // Outline points extrapolated by (a, b) = (0.3, 0.6), (0.5, 0), (0.2, 0.9) spacings.
        const std::array<double, 9> c{1.9, -0.3, -0.6, -(1 - w) * 1.5, (1 - w) * 0.5, 0.0, -w * 2.1, w * 0.2, w * 0.9};
        const double k = 850.0;  // N/m
        const model::SeamTerm term(k, c);
        VecN<27> x;
        for (int i = 0; i < 27; ++i) x[i] = u(rng);
        const model::Local<9> l = term.evaluate(x, Derivatives::HESSIAN);
        const double h = 1e-6;
        for (int i = 0; i < 27; ++i) {
            VecN<27> p = x, m = x;
            p[i] += h;
            m[i] -= h;
            const double fd = (term.value(p) - term.value(m)) / (2 * h);
            EXPECT_NEAR(l.gradient[i], fd, 1e-7 * std::max(1.0, std::abs(fd))) << "w " << w << " coordinate " << i;
            const VecN<27> dg = (term.gradient(p) - term.gradient(m)) / (2 * h);
            for (int j = 0; j < 27; ++j) EXPECT_NEAR(l.hessian(j, i), dg[j], 1e-6 * k) << "w " << w << " (" << j << ", " << i << ")";
        }
        // Quadratic: the value is k |d|^2 / 2; the Hessian is PSD, projected = exact.
        const Vec3 d = model::SeamTerm::gap(x, c);
        EXPECT_NEAR(l.value, 0.5 * k * d.squaredNorm(), 1e-15);
        const model::Local<9> p = term.evaluate(x, Derivatives::PROJECTED);
        EXPECT_EQ((p.hessian - l.hessian).cwiseAbs().maxCoeff(), 0.0);
        Eigen::SelfAdjointEigenSolver<MatN<27>> es(l.hessian, Eigen::EigenvaluesOnly);
        EXPECT_GE(es.eigenvalues().minCoeff(), -1e-9);
        // c c^T (x) I: the one non-zero eigenvalue k |c|^2, thrice.
        double c2 = 0;
        for (double ci : c) c2 += ci * ci;
        EXPECT_NEAR(es.eigenvalues().maxCoeff(), k * c2, 1e-9 * k * c2);
    }
}

TEST(SeamTerm, OutlinePointsOfAFlatCutAreOnTheOutline)
{
    // At the start (the pieces wrapped unstrained), each edge particle's extrapolated outline
    // point is the wrap of its outline point: the seam's two edges meet where the pattern says.
    for (double grain : {0.0, kPi / 4, 0.3}) {
        const model::GarmentCloth g = model::cut_pattern(two_panels(grain, 0.081), 0.005, "test");
        const std::vector<double> gaps = model::stitch_gaps(g.seams, g.start);
        ASSERT_FALSE(gaps.empty());
        // Extrapolating along a thread by up to a 5 mm spacing on the 10 cm cylinder misses the
        // arc by up to sigma^2 / (2 R) = 1.25e-4 m (measured 1.5e-4 and 1.8e-4 m with the
        // interpolation between points): 3e-4 m is 0.06 spacings.
        EXPECT_LT(*std::max_element(gaps.begin(), gaps.end()), 3e-4) << "grain " << grain;
        // The particles themselves start up to two spacings apart across the seam.
        double apart = 0;
        for (const model::Stitch& st : g.seams.stitches) apart = std::max(apart, (g.start[st.p] - g.start[st.q1]).norm());
        EXPECT_GT(apart, 0.001);
    }
}

/// Two 4 x 3 rectangles 1 cm apart on a grid, sewn along their facing sides.
model::Pattern two_panels(double grain_b, double height_b)
{
    auto rect = [](const std::string& name, double w, double h) {
        model::PatternPiece p;
        p.name = name;
        const Vec2 c[4] = {{0, 0}, {w, 0}, {w, h}, {0, h}};
        const char* names[4] = {"bottom", "right", "top", "left"};
        for (int k = 0; k < 4; ++k) {
            model::OutlineSegment s;
            s.name = names[k];
            s.a = c[k];
            s.b = c[(k + 1) % 4];
            p.segments.push_back(s);
        }
        p.placement.wrap = model::Placement::Wrap::CYLINDER;
        p.placement.radius = 0.1;
        p.placement.height = 1.0;
        return p;
    };
    model::Pattern pat;
    pat.pieces.push_back(rect("a", 0.061, 0.081));
    pat.pieces.push_back(rect("b", 0.061, height_b));
    pat.pieces[1].grain = grain_b;
    pat.pieces[1].placement.azimuth = 0.061 / 0.1;
    model::PatternSeam seam;
    seam.piece_a = 0;
    seam.segment_a = 1;  // a's right side, running up
    seam.piece_b = 1;
    seam.segment_b = 3;  // b's left side, running down
    seam.reversed = true;
    pat.seams.push_back(seam);
    return pat;
}

TEST(SeamTerm, InsideTheModelMatchesCentralDifferences)
{
    const model::GarmentCloth g = model::cut_pattern(two_panels(), 0.01, "test");
    kes::FittedFabric f;
    f.name = "test";
    f.areal_density_mg_cm2 = kCottonW / units::kMgPerCm2ToKgPerM2;
    f.bending_warp = fitted_bending(cotton_warp());
    f.bending_weft = fitted_bending(cotton_weft());
    f.shear = fitted_shear(cotton_shear());
    model::ModelOptions o;
    model::ClothModel cm(f, g.grid, o, g.active, g.area);
    cm.set_seams(g.seams, 400.0);
    // The start wrapped on the cylinder, each particle moved a little.
    Positions x = g.start;
    std::mt19937 rng(3);
    std::normal_distribution<double> n(0.0, 0.001);
    for (Vec3& p : x) p += Vec3(n(rng), n(rng), n(rng));
    const model::EnergyTerms e = cm.evaluate(x);
    EXPECT_GT(e.seam, 0.0);
    const Eigen::VectorXd g_exact = model_gradient(cm, x);
    const Eigen::VectorXd g_fd = fd_gradient(cm, x, 1e-7);
    EXPECT_LE(max_relative_error(g_fd, g_exact), 1e-5);
    // The stitches' particles are coupled in the Hessian's pattern.
    for (const model::Stitch& s : cm.seams().stitches) {
        EXPECT_TRUE(cm.stencils().coupled(s.p, s.q1));
        EXPECT_TRUE(cm.stencils().coupled(s.p, s.q2));
    }
    // The seam energy alone: its Hessian (exact) against differences of its gradient.
    cm.set_seam_stiffness(0.0);
    const Eigen::VectorXd g0 = model_gradient(cm, x);
    cm.set_seam_stiffness(400.0);
    EXPECT_NEAR(cm.evaluate(x).seam, e.seam, 1e-15);
    const Eigen::MatrixXd H = model_hessian(cm, x);
    cm.set_seam_stiffness(0.0);
    const Eigen::MatrixXd H0 = model_hessian(cm, x);
    cm.set_seam_stiffness(400.0);
    Positions y = x;
    const int p = cm.seams().stitches[2].p;
    const double h = 1e-6;
    y[p].x() += h;
    const Eigen::VectorXd gp = model_gradient(cm, y);
    y[p].x() -= 2 * h;
    const Eigen::VectorXd gm = model_gradient(cm, y);
    const Eigen::VectorXd col = (gp - gm) / (2 * h);
    y[p].x() += h;
    cm.set_seam_stiffness(0.0);
    y[p].x() += h;
    const Eigen::VectorXd gp0 = model_gradient(cm, y);
    y[p].x() -= 2 * h;
    const Eigen::VectorXd gm0 = model_gradient(cm, y);
    const Eigen::VectorXd col0 = (gp0 - gm0) / (2 * h);
    const Eigen::VectorXd seam_col = col - col0, seam_exact = (H - H0).col(3 * p);
    EXPECT_LE((seam_col - seam_exact).cwiseAbs().maxCoeff(), 1e-5 * seam_exact.cwiseAbs().maxCoeff());
    (void)g0;
}

// ---------------------------------------------------------------------------------------------
// Cutting and sewing.

TEST(GarmentPattern, PiecesAreDisjointRegionsOfOneGridWithTheirAreas)
{
    const double sigma = 0.005;
    const model::GarmentCloth g = model::cut_pattern(two_panels(kPi / 4), sigma, "test");
    ASSERT_EQ(g.cuts.size(), 2u);
    double area[2] = {0, 0};
    int count[2] = {0, 0};
    for (int p = 0; p < g.grid.size(); ++p) {
        EXPECT_LE(g.cuts[0].active[p] + g.cuts[1].active[p], 1) << "particle " << p << " in both pieces";
        if (g.piece_of[p] >= 0) {
            area[g.piece_of[p]] += g.area[p];
            ++count[g.piece_of[p]];
        }
    }
    EXPECT_NEAR(area[0], 0.061 * 0.081, 1e-12);
    EXPECT_NEAR(area[1], 0.061 * 0.101, 1e-12);  // turned 45 degrees on the grid: the same area
    // No thread joins two pieces: every 4-neighbour of a piece's particle is of the same piece or none.
    for (int p = 0; p < g.grid.size(); ++p) {
        if (g.piece_of[p] < 0) continue;
        const int i = p % g.grid.nu;
        for (int q : {p - 1, p + 1, p - g.grid.nu, p + g.grid.nu}) {
            if (q < 0 || q >= g.grid.size() || std::abs(q % g.grid.nu - i) > 1) continue;
            if (g.piece_of[q] >= 0) EXPECT_EQ(g.piece_of[q], g.piece_of[p]);
        }
    }
    // Each piece's particle count is its area over sigma^2 to within its perimeter.
    EXPECT_NEAR(count[0], 0.061 * 0.081 / (sigma * sigma), 2 * (0.061 + 0.081) / sigma);
    EXPECT_NEAR(count[1], 0.061 * 0.101 / (sigma * sigma), 2 * (0.061 + 0.101) / sigma);
}

TEST(GarmentPattern, TheGrainTurnsThePieceOnTheThreads)
{
    // Straight grain: a particle's weft neighbour is sigma along the piece's x; on the bias
    // (45 degrees), along (cos 45, -sin 45) or (cos 45, sin 45): turned by the grain.
    for (double grain : {0.0, kPi / 4}) {
        const model::GarmentCloth g = model::cut_pattern(two_panels(grain), 0.005, "test");
        for (int p = 0; p < g.grid.size() - 1; ++p) {
            if (g.piece_of[p] != 1 || g.piece_of[p + 1] != 1) continue;
            const Vec2 d = g.piece_point[p + 1] - g.piece_point[p];
            EXPECT_NEAR(d.norm(), 0.005, 1e-12);
            EXPECT_NEAR(std::atan2(d.y(), d.x()), grain, 1e-9);
            break;
        }
    }
}

TEST(GarmentPattern, EdgeParticlesLieAlongTheirSegmentsByArcLength)
{
    const double sigma = 0.005;
    const model::GarmentCloth g = model::cut_pattern(two_panels(kPi / 4), sigma, "test");
    for (int k = 0; k < 2; ++k)
        for (std::size_t m = 0; m < 4; ++m) {
            const model::EdgeParticles& e = g.edges[k][m];
            ASSERT_GE(e.particles.size(), 8u) << "piece " << k << " segment " << m;
            for (std::size_t i = 1; i < e.s.size(); ++i) EXPECT_GE(e.s[i], e.s[i - 1]);
            // Within a spacing of the outline.
            const model::PatternPiece piece = two_panels(kPi / 4).pieces[k];
            for (int p : e.particles) {
                double d = 0;
                piece.segments[m].project(g.piece_point[p], &d);
                EXPECT_LE(d, 1.0001 * sigma);  // a particle one row in from an outline on a grid line
            }
        }
}

TEST(GarmentPattern, StitchesJoinEdgesOfDifferentCountsByArcLength)
{
    // a's right side is 8.1 cm on the straight grain, b's left 10.1 cm on the bias: different
    // counts; each stitch's target is at the same fraction of the other edge's length.
    const double sigma = 0.005;
    const model::Pattern pat = two_panels(kPi / 4);
    const model::GarmentCloth g = model::cut_pattern(pat, sigma, "test");
    const model::EdgeParticles& A = g.edges[0][1];
    const model::EdgeParticles& B = g.edges[1][3];
    EXPECT_NE(A.particles.size(), B.particles.size());
    EXPECT_EQ(g.seams.stitches.size(), A.particles.size() + B.particles.size());
    const double La = pat.pieces[0].segments[1].length(), Lb = pat.pieces[1].segments[3].length();
    auto fraction_of = [&](int p) -> double {
        for (std::size_t i = 0; i < A.particles.size(); ++i)
            if (A.particles[i] == p) return A.s[i] / La;
        for (std::size_t i = 0; i < B.particles.size(); ++i)
            if (B.particles[i] == p) return 1.0 - B.s[i] / Lb;  // reversed
        return -1;
    };
    for (const model::Stitch& s : g.seams.stitches) {
        const double t = fraction_of(s.p), t1 = fraction_of(s.q1), t2 = fraction_of(s.q2);
        ASSERT_GE(t, 0.0);
        ASSERT_NE(s.q1, s.q2);
        if (s.w >= 0 && s.w <= 1) {  // between two particles; beyond an end, their line extended
            EXPECT_LE(t1, t + 1e-12);
            EXPECT_GE(t2, t - 1e-12);
        }
        EXPECT_NEAR((1 - s.w) * t1 + s.w * t2, t, 1e-12);
    }
    // The stitched pairs are not repelled (between two particles; beyond an edge's end the second may be further).
    for (const model::Stitch& s : g.seams.stitches)
        if (s.w >= 0 && s.w <= 1)
            EXPECT_TRUE(std::binary_search(g.seams.unrepelled.begin(), g.seams.unrepelled.end(),
                                           model::Stencil<2>{std::min(s.p, s.q1), std::max(s.p, s.q1)}));
}

TEST(GarmentPattern, TheWrapIsAnIsometry)
{
    // Distances along the cone's and the cylinder's surfaces between neighbouring points equal
    // the flat ones to second order: a 1 mm step keeps its length to 1e-5 relative (the chord of
    // a 1 mm arc on the 16 cm cylinder is 1.6e-9 m shorter).
    model::Placement cone;
    cone.wrap = model::Placement::Wrap::CONE;
    cone.half_angle = 20 * kPi / 180;
    cone.height = 1.4;
    model::Placement cyl;
    cyl.radius = 0.16;
    cyl.height = 1.0;
    for (const model::Placement& pl : {cone, cyl})
        for (double a : {0.0, 0.7, 2.0}) {
            const Vec2 p = Vec2(0.05, -0.4) + 0.1 * Vec2(std::cos(a), std::sin(a));
            for (double b : {0.0, 1.0, 2.5}) {
                const Vec2 q = p + 0.001 * Vec2(std::cos(b), std::sin(b));
                EXPECT_NEAR((model::place_point(pl, q) - model::place_point(pl, p)).norm(), 0.001, 1e-8);
            }
        }
    // The cone's apex stays on the axis at its height; the down direction runs down the body.
    EXPECT_NEAR(model::place_point(cone, Vec2::Zero()).norm() - 1.4, 0.0, 1e-12);
    const Vec3 below = model::place_point(cone, Vec2(0, -1));
    EXPECT_NEAR(below.z(), 1.4 - std::cos(cone.half_angle), 1e-12);
    EXPECT_NEAR(below.x(), std::sin(cone.half_angle), 1e-12);  // azimuth 0: +x
    // Right in the piece is increasing azimuth.
    EXPECT_GT(model::place_point(cone, Vec2(0.1, -1)).y(), 0.0);
}

TEST(GarmentPattern, BadPatternsAreNamed)
{
    model::Pattern pat = two_panels();
    pat.pieces[0].segments[2].a.x() += 0.01;  // not closed
    try {
        (void)model::cut_pattern(pat, 0.01, "g.toml");
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()),
                  "g.toml: piece[1].segment: the outline is not closed: each segment must start where the last ended");
    }
    model::Pattern tiny = two_panels();
    try {
        (void)model::cut_pattern(tiny, 0.1, "g.toml");  // 10 cm spacing: no particle on the edges
        FAIL() << "expected an InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("g.toml: piece[1] (a)"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace woven::test
