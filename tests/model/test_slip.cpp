// Friction inside the weave (model/slip.hpp): the Jenkins elements' energy and its derivatives,
// the return mapping, closed-form loops, the signed curvature, and the friction terms of a
// FRICTION model against central finite differences.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "model_test_support.hpp"
#include "woven/model/slip.hpp"

namespace woven::model {
namespace {

/// Bending-like (constant half width 0.05 gf.cm/cm, rise 0.3 1/cm), shear-like growing and
/// shrinking half widths (q = sin phi).
SlipLaw bending_law() { return make_slip_law(1.0, 0.05, 1.0, 0.05, 0.3); }
SlipLaw growing_law() { return make_slip_law(std::sin(0.5 * units::kDegToRad), 1.2, std::sin(5 * units::kDegToRad), 2.0, std::sin(0.3 * units::kDegToRad)); }
SlipLaw shrinking_law() { return make_slip_law(0.01, 1.0, 0.1, 0.5, 0.005); }

TEST(SlipLaw, GradedElementsSumToTheHalfWidth)
{
    const SlipLaw law = bending_law();
    double total = 0;
    for (double w : law.share) total += w;
    EXPECT_NEAR(total, 1.0, 1e-15);
    EXPECT_DOUBLE_EQ(law.h0, 0.05);
    EXPECT_DOUBLE_EQ(law.dh, 0.0);
    EXPECT_NEAR(law.k, 2 * 0.05 / (0.3 * kSlipElements), 1e-15);
    const SlipLaw g = growing_law();
    EXPECT_NEAR(g.half_width(std::sin(0.5 * units::kDegToRad)), 1.2, 1e-12);
    EXPECT_NEAR(g.half_width(std::sin(5 * units::kDegToRad)), 2.0, 1e-12);
}

TEST(SlipLaw, ConstantThresholdIsTheHuberFunction)
{
    const SlipLaw law = bending_law();
    for (int e : {0, 3, 7})
        for (double s : {-0.2, 0.0, 0.13})
            for (double d : {-1.0, -0.05, -0.001, 0.0, 0.002, 0.02, 0.4}) {
                const double m = law.threshold(e), k = law.k;
                const double huber = std::abs(d) <= m / k ? 0.5 * k * d * d : m * std::abs(d) - m * m / (2 * k);
                const Scalar3 el = law.element(e, s + d, s);
                EXPECT_NEAR(el.value, huber, 1e-15 + 1e-12 * std::abs(huber)) << "e " << e << " s " << s << " d " << d;
                EXPECT_NEAR(el.d1, std::clamp(k * d, -m, m), 1e-15);
            }
}

TEST(SlipLaw, ElementDerivativesMatchCentralDifferences)
{
    std::mt19937 rng(7);
    for (const SlipLaw& law : {bending_law(), growing_law(), shrinking_law()}) {
        std::uniform_real_distribution<double> u(-0.3, 0.3);
        for (int trial = 0; trial < 200; ++trial) {
            const int e = trial % kSlipElements;
            const double s = 0.2 * u(rng), q = u(rng), h = 1e-7;
            const Scalar3 c = law.element(e, q, s), p = law.element(e, q + h, s), m = law.element(e, q - h, s);
            EXPECT_NEAR((p.value - m.value) / (2 * h), c.d1, 1e-7 * (1 + std::abs(c.d1))) << "q " << q << " s " << s;
            // d2 is piecewise constant: skip the few points whose difference straddles a kink.
            if (std::abs(p.d2 - m.d2) == 0) {
                EXPECT_NEAR((p.d1 - m.d1) / (2 * h), c.d2, 1e-6 * (1 + std::abs(c.d2)));
            }
        }
    }
}

TEST(SlipLaw, ReturnMappingKeepsTheForceAndUnloadsElastically)
{
    const SlipLaw law = growing_law();
    SlipState s{};
    const double q = 0.05;  // far past every element's yield
    const double before = law.total_force(q, s);
    EXPECT_NEAR(before, law.half_width(q), 1e-12);  // virgin, saturated: the half width
    law.update(q, s);
    EXPECT_NEAR(law.total_force(q, s), before, 1e-14);
    for (int e = 0; e < kSlipElements; ++e) EXPECT_NEAR(law.amplitude(q) * law.k * (q - s[e]), law.force(e, q, s[e]), 1e-14);
    // A small step back is elastic: every element's unscaled force falls by k dq.
    const double dq = 1e-5;
    EXPECT_NEAR(law.total_force(q - dq, s), law.amplitude(q - dq) * (before / law.amplitude(q) - kSlipElements * law.k * dq), 1e-12);
    // The energy of a step is zero at the state's own strain for an element at rest...
    SlipState rest{};
    EXPECT_EQ(law.energy(0.0, rest).value, 0.0);
}

/// One element driven 0 -> +A -> -A -> 0 in small steps, the state updated after each: its force
/// is the closed-form Jenkins loop (rigid-plastic with elastic k, threshold m).
TEST(SlipLaw, SingleElementLoopIsTheClosedForm)
{
    const SlipLaw law = bending_law();
    const int e = 5;
    const double m = law.threshold(e), k = law.k, A = 10 * m / k;
    double s = 0;
    std::vector<double> path;
    for (int i = 0; i <= 100; ++i) path.push_back(A * i / 100.0);
    for (int i = 1; i <= 200; ++i) path.push_back(A - 2 * A * i / 200.0);
    for (int i = 1; i <= 100; ++i) path.push_back(-A + A * i / 100.0);
    double q_prev = 0, f_closed = 0;
    for (double q : path) {
        // Closed form: the elastic trial from the previous force, clamped.
        f_closed = std::clamp(f_closed + k * (q - q_prev), -m, m);
        const double f = law.force(e, q, s);
        EXPECT_NEAR(f, f_closed, 1e-14) << "q " << q;
        SlipState st{};
        st[e] = s;
        law.update(q, st);
        s = st[e];
        q_prev = q;
    }
    // Back at 0 after the loop, the element holds -m (it slid back at -A and unloaded by k A).
    EXPECT_NEAR(f_closed, std::clamp(-m + k * A, -m, m), 1e-14);
}

/// All eight elements through a +-Q loop: the width at q is 2 h (Masing), the virgin rise follows
/// h r(q / q1) to within the eight pieces' error.
TEST(SlipLaw, EightElementLoopHasTheHalfWidthAndTheVirginRise)
{
    const SlipLaw law = bending_law();
    SlipState s{};
    const double Q = 2.5;
    std::vector<double> up, down;
    auto run = [&](double from, double to, int steps, std::vector<double>* record) {
        for (int i = 1; i <= steps; ++i) {
            const double q = from + (to - from) * i / steps;
            if (record) record->push_back(law.total_force(q, s));
            law.update(q, s);
        }
    };
    // Virgin rise against 0.05 r(q / 0.3): the eight linear pieces are within 1/(4 N^2) of h.
    for (int i = 1; i <= 30; ++i) {
        const double q = 0.3 * i / 30.0, u = q / 0.3;
        EXPECT_NEAR(law.total_force(q, SlipState{}), 0.05 * (1 - (1 - u) * (1 - u)), 0.05 / (4.0 * kSlipElements * kSlipElements));
    }
    run(0, Q, 25, nullptr);
    run(Q, -Q, 50, &down);  // q = Q - 0.1 i
    run(-Q, Q, 50, &up);    // q = -Q + 0.1 i
    // At q = +1: down[14] (Q - 1.5), up[34] (-Q + 3.5).
    EXPECT_NEAR(up[34] - down[14], 0.1, 1e-12);
    EXPECT_NEAR(down[14], -0.05, 1e-12);
}

// ---------------------------------------------------------------------------------------------

/// Five particles of a thread bent on a circle of curvature K (1/m) in the x-z plane, the
/// across neighbours along y.
VecN<15> arc(double K, double sigma)
{
    const double psi = 2 * std::asin(0.5 * K * sigma);  // turning angle per segment
    VecN<15> x;
    x.segment<3>(0) = Vec3(-sigma * std::cos(psi / 2), 0, sigma * std::sin(psi / 2));
    x.segment<3>(3) = Vec3(0, 0, 0);
    x.segment<3>(6) = Vec3(sigma * std::cos(psi / 2), 0, sigma * std::sin(psi / 2));
    x.segment<3>(9) = Vec3(0, -sigma, 0);
    x.segment<3>(12) = Vec3(0, sigma, 0);
    return x;
}

TEST(SlipCurvature, IsTheSignedCurvatureOfABentThread)
{
    const double sigma = 0.005;  // m
    for (double K_cm : {-2.5, -1.0, 0.0, 0.3, 1.0, 2.5}) {
        const VecN<15> x = arc(K_cm * 100.0, sigma);
        const SignedCurvature warp = signed_curvature(x, sigma * 100, false, false);
        const SignedCurvature weft = signed_curvature(x, sigma * 100, true, false);
        ASSERT_TRUE(warp.ok);
        // Bending up (+z) with w along +y: warp n = w x t = -z, weft n = +z.
        EXPECT_NEAR(weft.q, K_cm, 1e-9 * (1 + std::abs(K_cm)));
        EXPECT_NEAR(warp.q, -K_cm, 1e-9 * (1 + std::abs(K_cm)));
    }
    // No across chord: no sign, no friction.
    VecN<15> x = arc(100.0, sigma);
    x.segment<3>(9) = x.segment<3>(12) = x.segment<3>(3);
    EXPECT_FALSE(signed_curvature(x, 0.5, false, true).ok);
}

TEST(SlipCurvature, DerivativesMatchCentralDifferences)
{
    std::mt19937 rng(11);
    std::normal_distribution<double> n(0.0, 1.0);
    const double sigma = 0.01;
    for (int trial = 0; trial < 20; ++trial) {
        VecN<15> x = arc(30.0 * n(rng), sigma);
        for (int i = 0; i < 15; ++i) x[i] += 0.15 * sigma * n(rng);
        const bool weft = trial % 2;
        const SignedCurvature sc = signed_curvature(x, sigma * 100, weft, true);
        ASSERT_TRUE(sc.ok);
        EXPECT_NEAR(signed_curvature(x, sigma * 100, weft, false).q, sc.q, 1e-12 * (1 + std::abs(sc.q)));
        const double h = 1e-6 * sigma;
        VecN<15> g;
        MatN<15> H;
        for (int i = 0; i < 15; ++i) {
            VecN<15> p = x, m = x;
            p[i] += h;
            m[i] -= h;
            const SignedCurvature sp = signed_curvature(p, sigma * 100, weft, true), sm = signed_curvature(m, sigma * 100, weft, true);
            g[i] = (sp.q - sm.q) / (2 * h);
            H.col(i) = (sp.gradient - sm.gradient) / (2 * h);
        }
        EXPECT_LT(test::max_relative_error(g, sc.gradient), 1e-6) << "trial " << trial;
        EXPECT_LT(test::max_relative_error(H, sc.hessian), 1e-5) << "trial " << trial;
        EXPECT_LT((sc.hessian - sc.hessian.transpose()).norm(), 1e-9 * sc.hessian.norm());
    }
}

// ---------------------------------------------------------------------------------------------

/// A FRICTION model on a small grid with only the spacing terms and the friction (zero elastic
/// curves), laws given.
ClothModel friction_model(const Grid& grid, Discretization d)
{
    kes::FittedFabric f;
    f.name = "slip";
    f.areal_density_mg_cm2 = test::kCottonW / units::kMgPerCm2ToKgPerM2;
    f.bending_warp = f.bending_weft = test::zero_curve(2.5);
    f.shear = test::zero_curve(8.0);
    ModelOptions o;
    o.discretization = d;
    o.gravity = 0;
    o.C0 = test::cotton_C0(grid.sigma);
    o.hysteresis = Hysteresis::FRICTION;
    o.shear_scale = 1.1;
    SlipLaws laws;
    laws.warp = make_slip_law(1.0, 0.04, 1.0, 0.04, 0.3);
    laws.weft = make_slip_law(1.0, 0.06, 1.0, 0.06, 0.3);
    laws.shear = growing_law();
    return ClothModel(f, grid, o, {}, {}, laws);
}

class SlipModel : public testing::TestWithParam<Discretization> { };

TEST_P(SlipModel, GradientAndHessianMatchCentralDifferences)
{
    const Grid grid{5, 4, 0.01};
    ClothModel m = friction_model(grid, GetParam());
    ASSERT_TRUE(m.has_slip());
    ASSERT_EQ(m.stencils().warp_slip_bends.size(), m.stencils().warp_bends.size());
    // A state with slip: a sheared, bent configuration, then a nearby one (some elements
    // sliding on, some unloading elastically).
    const Positions x0 = test::perturbed_grid(grid, 3, 0.08);
    m.update_slip(x0);
    for (unsigned seed : {4u, 5u}) {
        Positions x = x0;
        std::mt19937 rng(seed);
        std::normal_distribution<double> n(0.0, 0.004 * grid.sigma);
        for (Vec3& p : x) p += Vec3(n(rng), n(rng), n(rng));
        const EnergyTerms e = m.evaluate(x);
        EXPECT_GT(std::abs(e.bending_warp) + std::abs(e.bending_weft), 0);
        EXPECT_GT(e.trellis, 0);
        const Eigen::VectorXd g = test::model_gradient(m, x);
        const Eigen::VectorXd fd = test::fd_gradient(m, x, 1e-7);
        EXPECT_LT(test::max_relative_error(fd, g), 1e-5) << "seed " << seed;
        const Eigen::MatrixXd H = test::model_hessian(m, x);
        const Eigen::MatrixXd fdH = test::fd_hessian(m, x, 1e-8);
        EXPECT_LT(test::max_relative_error(fdH, H), 1e-4) << "seed " << seed;
        // The projected Hessian is PSD stencil by stencil, hence in total.
        const Eigen::MatrixXd P = test::model_hessian(m, x, Derivatives::PROJECTED);
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(P);
        EXPECT_GT(es.eigenvalues().minCoeff(), -1e-9 * es.eigenvalues().cwiseAbs().maxCoeff());
    }
    // reset_slip: the flat grid has no friction energy again.
    m.reset_slip();
    const EnergyTerms flat = m.evaluate(flat_grid(grid, Vec3::Zero(), 0.2));
    EXPECT_LT(std::abs(flat.bending_warp + flat.bending_weft + flat.trellis), 1e-25);  // rounding of the rotated grid
}

INSTANTIATE_TEST_SUITE_P(Discretizations, SlipModel, testing::Values(Discretization::PAPER, Discretization::CONVERGENT),
                         [](const auto& info) { return info.param == Discretization::PAPER ? std::string("Paper") : std::string("Convergent"); });

TEST(SlipModel, FrictionOnlyForCurvesGivenWithAWidth)
{
    kes::FabricData f;
    f.name = "f";
    f.areal_density_mg_cm2 = 10;
    f.bending_warp.summary = kes::BendingSummary{0.1, 0.06};
    f.bending_warp.curve = kes::synthesize_bending_curve(*f.bending_warp.summary);
    f.bending_weft.curve = kes::synthesize_bending_curve({0.08, 0.05});  // points: no summary
    f.shear.summary = kes::ShearSummary{1.0, 0.0, 0.0};
    f.shear.curve = kes::synthesize_shear_curve(*f.shear.summary);
    const SlipLaws laws = slip_laws(f);
    EXPECT_TRUE(laws.warp.active());
    EXPECT_NEAR(laws.warp.half_width(1.0), 0.03, 1e-15);
    EXPECT_FALSE(laws.weft.active());
    EXPECT_FALSE(laws.shear.active());
    // The elastic part is the mean line where a width is given, the curve itself elsewhere.
    const kes::FabricData mean = kes::without_hysteresis(f);
    EXPECT_NEAR(mean.bending_warp.curve.y[20], 0.1 * mean.bending_warp.curve.x[20], 1e-15);
    EXPECT_EQ(mean.bending_weft.curve.y, f.bending_weft.curve.y);
    const ModelOptions loading;
    EXPECT_FALSE(make_cloth_model(f, Grid{4, 4, 0.01}, loading).has_slip());
    ModelOptions friction;
    friction.hysteresis = Hysteresis::FRICTION;
    const ClothModel m = make_cloth_model(f, Grid{4, 4, 0.01}, friction);
    EXPECT_TRUE(m.has_slip());
    EXPECT_NEAR(m.bending_warp().moment().value(1.0), 0.1, 1e-9);  // B K, not B K + 2HB/2
}

}  // namespace
}  // namespace woven::model
