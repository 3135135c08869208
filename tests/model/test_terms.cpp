// The terms of Eq. (1) on their own stencils (model/terms.hpp), directly: gradient against
// fourth-order central differences of the value, exact Hessian against central differences of
// the gradient, projected Hessian symmetric PSD, the per-particle blocks equal to the full
// stencil's. Random stencils and near-degenerate ones (theta near pi and near 0, phi near 0 and
// near the singular 1.05 rad, r near sigma and near 0), fixed seeds. Also the stencil lists
// (model/stencils.hpp) with and without an active mask.
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "model/model_test_support.hpp"
#include "woven/model/stencils.hpp"
#include "woven/model/terms.hpp"

namespace woven::test {
namespace {

using model::Derivatives;

constexpr double kSigma = 0.02;              // m
constexpr double kStep = 1e-6 * kSigma;      // FD step (m)
constexpr double kGradientTolerance = 1e-6;  // max_relative_error of the gradient
constexpr double kHessianTolerance = 1e-5;   // of the Hessian
constexpr double kPi = std::numbers::pi;

/// Fourth-order central differences of f along each coordinate of x.
template <int D, class F> auto central(const VecN<D>& x, F f)
{
    using Out = decltype(f(x));
    Out g[D];
    for (int k = 0; k < D; ++k) {
        auto at = [&](double s) {
            VecN<D> y = x;
            y[k] += s;
            return f(y);
        };
        g[k] = (8.0 * (at(kStep) - at(-kStep)) - (at(2 * kStep) - at(-2 * kStep))) / (12.0 * kStep);
    }
    return std::vector<Out>(g, g + D);
}

/// Checks a term at x: gradient (if `check_gradient`) and exact Hessian (if `check_hessian`)
/// against finite differences, projected Hessian PSD, particle blocks.
template <class T> void check_term(const T& term, const typename T::X& x, bool check_gradient, bool check_hessian)
{
    constexpr int D = 3 * T::kParticles;
    const model::Local<T::kParticles> g = term.evaluate(x, Derivatives::GRADIENT);
    ASSERT_TRUE(std::isfinite(g.value));
    if (g.vanishes) {
        EXPECT_EQ(g.value, 0.0);
        EXPECT_EQ(term.gradient(x).cwiseAbs().maxCoeff(), 0.0);
        return;
    }
    if (check_gradient) {
        const auto fd = central<D>(x, [&](const VecN<D>& y) { return term.value(y); });
        Eigen::VectorXd fdv(D);
        for (int k = 0; k < D; ++k) fdv[k] = fd[k];
        EXPECT_LE(max_relative_error(fdv, g.gradient), kGradientTolerance)
            << "value " << g.value << " J, gradient " << g.gradient.transpose();
    }
    const MatN<D> H = term.hessian(x);
    EXPECT_LE((H - H.transpose()).cwiseAbs().maxCoeff(), 1e-12 * H.cwiseAbs().maxCoeff());
    if (check_hessian) {
        const auto fd = central<D>(x, [&](const VecN<D>& y) { return Eigen::VectorXd(term.gradient(y)); });
        Eigen::MatrixXd fdm(D, D);
        for (int k = 0; k < D; ++k) fdm.col(k) = fd[k];
        EXPECT_LE(max_relative_error(fdm, H), kHessianTolerance) << "max |H| " << H.cwiseAbs().maxCoeff();
    }
    // Projected: same value and gradient, symmetric PSD.
    const model::Local<T::kParticles> p = term.evaluate(x, Derivatives::PROJECTED);
    EXPECT_EQ(p.value, g.value);
    EXPECT_LE((p.gradient - g.gradient).cwiseAbs().maxCoeff(), 1e-14 * g.gradient.cwiseAbs().maxCoeff());
    EXPECT_LE((p.hessian - p.hessian.transpose()).cwiseAbs().maxCoeff(), 1e-12 * p.hessian.cwiseAbs().maxCoeff());
    Eigen::SelfAdjointEigenSolver<MatN<D>> es(0.5 * (p.hessian + p.hessian.transpose()), Eigen::EigenvaluesOnly);
    EXPECT_GE(es.eigenvalues().minCoeff(), -1e-10 * es.eigenvalues().cwiseAbs().maxCoeff()) << es.eigenvalues().transpose();
    // The per-particle blocks (paper solver) are the full stencil's.
    for (int k = 0; k < T::kParticles; ++k) {
        const model::ParticleLocal b = term.particle(x, k, Derivatives::PROJECTED);
        EXPECT_EQ(b.value, g.value);
        EXPECT_LE((b.gradient - p.gradient.template segment<3>(3 * k)).cwiseAbs().maxCoeff(),
                  1e-14 * p.gradient.cwiseAbs().maxCoeff() + 1e-300);
        EXPECT_LE((b.hessian - p.hessian.template block<3, 3>(3 * k, 3 * k)).cwiseAbs().maxCoeff(),
                  1e-13 * p.hessian.cwiseAbs().maxCoeff() + 1e-300);
    }
}

/// A rigid motion of a stencil (random rotation, a translation near z = 0.01 m, where gravity's
/// rounding stays small).
template <int D> VecN<D> placed(const VecN<D>& local, unsigned seed)
{
    const Mat3 Q = random_rotation(seed);
    VecN<D> out;
    for (int k = 0; k < D / 3; ++k) out.template segment<3>(3 * k) = Q * local.template segment<3>(3 * k) + Vec3(0.3, -0.2, 0.01);
    return out;
}

// ---------------------------------------------------------------------------------------------
// Pair terms and gravity.

struct PairCase {
    double r;  ///< distance / sigma
    unsigned seed;
};
class PairTerms : public testing::TestWithParam<PairCase> {};

TEST_P(PairTerms, GradientAndHessianMatchFiniteDifferences)
{
    const auto [r, seed] = GetParam();
    const model::ThreadSpacing spacing{cotton_C0(kSigma), kSigma};
    VecN<6> x;
    x << Vec3::Zero(), r * kSigma * Vec3(0.6, 0.0, 0.8);
    x = placed<6>(x, seed);
    {
        SCOPED_TRACE("stretch");
        check_term(model::StretchTerm(spacing), x, true, true);
    }
    {
        SCOPED_TRACE("repulsion");
        check_term(model::RepulsionTerm(spacing), x, true, true);
    }
    // Exactly one of the two is active off r = sigma.
    EXPECT_NE(model::StretchTerm(spacing).evaluate(x, Derivatives::NONE).vanishes,
              model::RepulsionTerm(spacing).evaluate(x, Derivatives::NONE).vanishes);
}
INSTANTIATE_TEST_SUITE_P(Radii, PairTerms,
                         testing::Values(PairCase{0.02, 1}, PairCase{0.1, 2}, PairCase{0.5, 3}, PairCase{0.9, 4}, PairCase{0.99, 5},
                                         PairCase{0.999, 6}, PairCase{1.001, 7}, PairCase{1.01, 8}, PairCase{1.05, 9}, PairCase{1.2, 10},
                                         PairCase{1.5, 11}));

// The convergent thread with a soft compression (ModelOptions::thread_compression): the stretch
// term's derivatives on either side of the rest length, where the stiffness jumps.
TEST(PairTerms, SoftCompressionMatchesFiniteDifferences)
{
    const model::ThreadSpacing spacing{cotton_C0(kSigma), kSigma, 500.0, 0.25};
    for (const double r : {0.9, 0.995, 1.005, 1.1}) {
        SCOPED_TRACE(r);
        VecN<6> x;
        x << Vec3::Zero(), r * kSigma * Vec3(0.6, 0.0, 0.8);
        check_term(model::StretchTerm(spacing), placed<6>(x, 3), true, true);
    }
}

TEST(PairTerms, SingularAndOutOfRange)
{
    const model::ThreadSpacing spacing{cotton_C0(kSigma), kSigma};
    VecN<6> same;
    same << Vec3(0.1, 0.2, 0.3), Vec3(0.1, 0.2, 0.3);
    EXPECT_TRUE(std::isinf(model::RepulsionTerm(spacing).evaluate(same, Derivatives::PROJECTED).value));
    VecN<6> at_sigma;
    at_sigma << Vec3::Zero(), Vec3(kSigma, 0, 0);
    EXPECT_TRUE(model::StretchTerm(spacing).evaluate(at_sigma, Derivatives::HESSIAN).vanishes);
    EXPECT_TRUE(model::RepulsionTerm(spacing).evaluate(at_sigma, Derivatives::HESSIAN).vanishes);
}

TEST(Gravity, ValueGradientAndZeroHessian)
{
    // m g z = 4.8e-5 kg * 9.80665 m/s^2 * 0.5 m = 2.35359...e-4 J; gradient (0, 0, m g).
    const model::GravityTerm t(4.8e-5, units::kStandardGravity);
    const Vec3 x(0.3, -0.1, 0.5);
    EXPECT_NEAR(t.value(x), 4.8e-5 * 9.80665 * 0.5, 1e-18);
    EXPECT_EQ(t.gradient(x), Vec3(0, 0, 4.8e-5 * 9.80665));
    EXPECT_EQ(t.hessian(x).cwiseAbs().maxCoeff(), 0.0);
    check_term(t, x, true, true);
}

// ---------------------------------------------------------------------------------------------
// Bending: three particles, theta from a fold (0.05) to straight (pi).

struct AngleCase {
    std::string name;
    double angle;  ///< theta (bending) or phi (trellis), rad
    unsigned seed;
};
std::string angle_case_name(const testing::TestParamInfo<AngleCase>& i) { return i.param.name; }

VecN<9> bend(double theta, unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> len(0.9 * kSigma, 1.1 * kSigma);
    const double la = len(rng), lb = len(rng);
    VecN<9> x;
    x << la * Vec3::UnitX(), Vec3::Zero(), lb * Vec3(std::cos(theta), std::sin(theta), 0);
    return placed<9>(x, seed + 500);
}

class Bending : public testing::TestWithParam<AngleCase> {};

TEST_P(Bending, GradientMatchesFiniteDifferences)
{
    // Near a straight thread B(c) carries an absolute rounding of eps |dB/dc| (c is rounded
    // where 1 + c ~ (pi - theta)^2 / 2), so a difference of values cannot reach 1e-6 there: the
    // gradient is checked against its geometric form instead, within 1e-2 rad of straight (|dE/dx0| = |dB/dc| sin(theta) /
    // |a|, perpendicular to a; the three forces sum to zero).
    const double theta = GetParam().angle;
    const VecN<9> x = bend(theta, GetParam().seed);
    for (const Curves& curves : {Curves::fitted(), Curves::smooth()})
        for (auto form : {model::BendingForm::SECANT, model::BendingForm::WORK}) {
            const model::BendingEnergy energy(curves.weft, kSigma, form, units::GramForce::PAPER);
            const model::BendingTerm term(energy);
            if (kPi - theta > 1e-2) {
                check_term(term, x, true, false);
                continue;
            }
            const VecN<9> g = term.gradient(x);
            const Vec3 a = x.head<3>() - x.segment<3>(3), b = x.tail<3>() - x.segment<3>(3);
            const double f1 = std::abs(energy.of_cosine(std::cos(theta)).d1);
            const double floor = 1e-14 * f1 / std::min(a.norm(), b.norm());
            EXPECT_NEAR(g.head<3>().norm(), f1 * std::sin(theta) / a.norm(), 1e-6 * f1 * std::sin(theta) / a.norm() + floor);
            EXPECT_NEAR(g.tail<3>().norm(), f1 * std::sin(theta) / b.norm(), 1e-6 * f1 * std::sin(theta) / b.norm() + floor);
            EXPECT_LE(std::abs(g.head<3>().dot(a.normalized())), floor);
            EXPECT_LE((g.head<3>() + g.segment<3>(3) + g.tail<3>()).norm(), floor);
        }
}

TEST_P(Bending, ExactHessianMatchesFiniteDifferencesProjectedIsPositiveSemiDefinite)
{
    // Smooth single-segment curves: the fitted ones are only C1 at their junctions.
    const VecN<9> x = bend(GetParam().angle, GetParam().seed);
    for (auto form : {model::BendingForm::SECANT, model::BendingForm::WORK}) {
        const model::BendingEnergy energy(Curves::smooth().warp, kSigma, form, units::GramForce::PAPER);
        check_term(model::BendingTerm(energy), x, false, true);
    }
}

std::vector<AngleCase> bending_cases()
{
    std::vector<AngleCase> c;
    const std::pair<const char*, double> thetas[] = {
        {"straight", kPi},    {"pi_minus_1e6", kPi - 1e-6},         {"pi_minus_1e3", kPi - 1e-3},         {"t3", 3.0},  {"t2", 2.0},
        {"half_pi", kPi / 2}, {"quarter_pi_above", kPi / 4 + 1e-4}, {"quarter_pi_below", kPi / 4 - 1e-4}, {"t05", 0.5}, {"t02", 0.2},
        {"fold005", 0.05}};
    unsigned seed = 10;
    for (auto [n, t] : thetas) c.push_back({n, t, seed++});
    std::mt19937 rng(99);
    std::uniform_real_distribution<double> u(0.1, kPi - 0.01);
    for (int k = 0; k < 8; ++k) c.push_back({"random" + std::to_string(k), u(rng), seed++});
    return c;
}
INSTANTIATE_TEST_SUITE_P(Sweep, Bending, testing::ValuesIn(bending_cases()), angle_case_name);

TEST(Bending, FoldedFlatIsInfinite)
{
    const model::BendingEnergy energy(Curves::fitted().warp, kSigma, model::BendingForm::SECANT, units::GramForce::PAPER);
    VecN<9> x;
    x << Vec3(kSigma, 0, 0), Vec3::Zero(), Vec3(0.9 * kSigma, 0, 0);  // theta = 0
    EXPECT_TRUE(std::isinf(model::BendingTerm(energy).value(x)));
}

// ---------------------------------------------------------------------------------------------
// Trellis: four particles L R D U around a crossing sheared by phi.

VecN<12> crossing(double phi, unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> len(0.9 * kSigma, 1.1 * kSigma);
    const Vec3 e1 = Vec3::UnitX(), w(std::cos(kPi / 2 + phi), std::sin(kPi / 2 + phi), 0);
    VecN<12> x;
    x << -len(rng) * e1, len(rng) * e1, -len(rng) * w, len(rng) * w;
    return placed<12>(x, seed + 700);
}

class Trellis : public testing::TestWithParam<AngleCase> {};

TEST_P(Trellis, GradientAndHessianMatchFiniteDifferences)
{
    // T is even with a |phi|^3 term, C2 but not C3 at 0: a difference whose step (1e-6 rad)
    // exceeds |phi| cannot reach 1e-6 on the gradient there; the Hessian (of the C1 gradient) is
    // still checked.
    const double phi = GetParam().angle;
    const VecN<12> x = crossing(phi, GetParam().seed);
    for (const Curves& curves : {Curves::fitted(), Curves::smooth()}) {
        const model::TrellisEnergy energy(curves.shear, kSigma, units::GramForce::PAPER);
        const bool smooth = curves.shear.segments().size() == 1;
        const double phi_e = energy.last_measured_angle();
        const bool near_junction = std::abs(std::abs(phi) - phi_e) < 1e-3;
        check_term(model::TrellisTerm(energy), x, std::abs(phi) > 1e-4, smooth && !near_junction);
    }
}

std::vector<AngleCase> trellis_cases()
{
    std::vector<AngleCase> c;
    const std::pair<const char*, double> phis[] = {{"zero", 0.0}, {"p1e7", 1e-7}, {"p1e3", 1e-3}, {"m005", -0.05}, {"p01", 0.1},
                                                   {"p03", 0.3},  {"m06", -0.6},  {"p10", 1.0},   {"m104", -1.04}};
    unsigned seed = 40;
    for (auto [n, p] : phis) c.push_back({n, p, seed++});
    std::mt19937 rng(98);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < 8; ++k) c.push_back({"random" + std::to_string(k), u(rng), seed++});
    return c;
}
INSTANTIATE_TEST_SUITE_P(Sweep, Trellis, testing::ValuesIn(trellis_cases()), angle_case_name);

TEST(Trellis, EqualsTheEnergyOfTheAngleAndIsInfinitePastTheSingularAngle)
{
    const model::TrellisEnergy energy(Curves::fitted().shear, kSigma, units::GramForce::PAPER);
    const model::TrellisTerm term(energy);
    for (double phi : {0.05, -0.2, 0.4})
        EXPECT_NEAR(term.value(crossing(phi, 3)), energy.of_angle(phi).value, 1e-12 * energy.of_angle(phi).value);
    EXPECT_TRUE(std::isinf(term.value(crossing(1.06, 3))));
}

// ---------------------------------------------------------------------------------------------
// Twist (bias bending, beyond the paper): a cell (i,j) (i+1,j) (i,j+1) (i+1,j+1).

constexpr double kTwistRigidity = 2e-5;  // N m: T of a cotton shirting (0.05 gf.cm^2/cm x 4)

/// A sigma x sigma cell on the surface z = w(u, v), placed by a random rigid motion.
template <class W> VecN<12> cell_on(W w, double u0, double v0, unsigned seed)
{
    VecN<12> x;
    int k = 0;
    for (double dv : {0.0, kSigma})
        for (double du : {0.0, kSigma}) x.segment<3>(3 * k++) = Vec3(u0 + du, v0 + dv, w(u0 + du, v0 + dv));
    return placed<12>(x, seed);
}

/// A cell of random shape: corners moved by up to a quarter spacing in every direction.
VecN<12> random_cell(unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-0.25 * kSigma, 0.25 * kSigma);
    VecN<12> x = cell_on([](double, double) { return 0.0; }, 0, 0, seed);
    for (int k = 0; k < 12; ++k) x[k] += u(rng);
    return x;
}

TEST(Twist, GradientAndHessianMatchFiniteDifferences)
{
    const model::TwistTerm term(kTwistRigidity, kSigma);
    for (unsigned seed = 900; seed < 916; ++seed) check_term(term, random_cell(seed), true, true);
    // Nearly flat and exactly flat cells (f = 0: the exact Hessian is the Gauss-Newton one).
    check_term(term, cell_on([](double u, double v) { return 1e-4 * u * v / kSigma; }, 0.01, 0.02, 917), true, true);
    check_term(term, cell_on([](double, double) { return 0.0; }, 0.01, 0.02, 918), false, true);
}

TEST(Twist, VanishesForBendsAlongEitherThreadAndForShear)
{
    const model::TwistTerm term(kTwistRigidity, kSigma);
    const double k = 20.0;  // 1/m: a tight bend, radius 5 cm
    auto along_u = [&](double u, double) { return 0.5 * k * u * u; };  // generators along v: bends the u thread
    auto along_v = [&](double, double v) { return 0.5 * k * v * v; };
    for (unsigned seed : {1u, 2u, 3u}) {
        EXPECT_LE(term.value(cell_on(along_u, 0.03, -0.01, seed)), 1e-25);
        EXPECT_LE(term.value(cell_on(along_v, -0.02, 0.05, seed)), 1e-25);
    }
    // A sheared (and rotated) parallelogram.
    VecN<12> x;
    const Vec3 a(kSigma, 0, 0), b(0.4 * kSigma, 0.9 * kSigma, 0);
    x << Vec3::Zero(), a, b, Vec3(a + b);
    EXPECT_LE(term.value(placed<12>(x, 7)), 1e-25);
}

TEST(Twist, StoresTheContinuumEnergyOfABendAcrossTheThreads)
{
    // A cylindrical bend of curvature k whose generators make angle alpha with the v thread:
    // tau = k cos(alpha) sin(alpha), the energy T tau^2 / 2 per unit area, sigma^2 per cell; the
    // cell's twist is exact for a quadratic surface, so only round-off separates them.
    const model::TwistTerm term(kTwistRigidity, kSigma);
    const double k = 5.0;
    for (double alpha : {0.3, kPi / 4, 1.1}) {
        const double c = std::cos(alpha), s = std::sin(alpha);
        auto w = [&](double u, double v) {
            const double across = c * u + s * v;  // distance across the generators
            return 0.5 * k * across * across;
        };
        const double tau = k * c * s;
        const double expected = 0.5 * kTwistRigidity * tau * tau * kSigma * kSigma;
        const double got = term.value(cell_on(w, 0.004, -0.003, 11));
        // The cell's normal tilts by O(k sigma) from the surface's at its centre: relative O((k sigma)^2).
        EXPECT_NEAR(got, expected, 2 * (k * kSigma) * (k * kSigma) * expected) << "alpha " << alpha;
    }
}

TEST(Twist, IsInfiniteWhenTheDiagonalsAreParallel)
{
    VecN<12> x;
    x << Vec3::Zero(), Vec3(kSigma, 0, 0), Vec3(kSigma, 0, 0), Vec3(2 * kSigma, 0, 0);
    EXPECT_TRUE(std::isinf(model::TwistTerm(kTwistRigidity, kSigma).value(x)));
}

// ---------------------------------------------------------------------------------------------
// Stencil lists.

TEST(Stencils, FullGridCountsAndCoupling)
{
    const model::Grid grid{5, 4, kSigma};
    const model::Stencils s = model::make_stencils(grid);
    EXPECT_EQ(s.particles.size(), 20u);
    EXPECT_EQ(s.edges.size(), static_cast<size_t>(4 * 4 + 5 * 3));
    EXPECT_EQ(s.warp_bends.size(), static_cast<size_t>(5 * 2));  // along j: nv - 2 per column
    EXPECT_EQ(s.weft_bends.size(), static_cast<size_t>(3 * 4));  // along i: nu - 2 per row
    EXPECT_EQ(s.crossings.size(), static_cast<size_t>(3 * 2));
    // Warp bends step by nu (along j), weft by 1 (along i); crossings are L R D U.
    EXPECT_EQ(s.warp_bends[0], (model::Stencil<3>{grid.index(0, 0), grid.index(0, 1), grid.index(0, 2)}));
    EXPECT_EQ(s.weft_bends[0], (model::Stencil<3>{grid.index(0, 0), grid.index(1, 0), grid.index(2, 0)}));
    EXPECT_EQ(s.crossings[0], (model::Stencil<4>{grid.index(0, 1), grid.index(2, 1), grid.index(1, 0), grid.index(1, 2)}));
    // An interior particle (2, 2) of a larger grid is coupled to itself and its 12 stencil
    // partners: (+-1, 0), (0, +-1), (+-2, 0), (0, +-2), (+-1, +-1).
    const model::Grid big{7, 7, kSigma};
    const model::Stencils b = model::make_stencils(big);
    EXPECT_EQ(b.coupled_with(big.index(3, 3)).size(), 13u);
    for (int p = 0; p < big.size(); ++p)
        for (int q : b.coupled_with(p)) EXPECT_TRUE(b.coupled(q, p)) << p << " " << q;
    EXPECT_FALSE(b.coupled(big.index(3, 3), big.index(5, 5)));
}

TEST(Stencils, MaskKeepsOnlyWhollyActiveStencils)
{
    const model::Grid grid{5, 5, kSigma};
    std::vector<char> active(grid.size(), 1);
    active[grid.index(2, 2)] = 0;  // a hole in the middle
    const model::Stencils s = model::make_stencils(grid, active);
    EXPECT_EQ(s.particles.size(), 24u);
    auto has = [](const auto& list, int p) {
        for (const auto& st : list)
            for (int q : st)
                if (q == p) return true;
        return false;
    };
    const int hole = grid.index(2, 2);
    EXPECT_FALSE(has(s.edges, hole));
    EXPECT_FALSE(has(s.warp_bends, hole));
    EXPECT_FALSE(has(s.weft_bends, hole));
    EXPECT_FALSE(has(s.crossings, hole));
    EXPECT_EQ(s.edges.size(), static_cast<size_t>(2 * 4 * 5 - 4));
    EXPECT_EQ(s.warp_bends.size(), static_cast<size_t>(15 - 3));  // the three with (2, 2) in them
    EXPECT_EQ(s.crossings.size(), static_cast<size_t>(9 - 5));    // at (2, 2) and its four neighbours
    ASSERT_EQ(s.coupled_with(hole).size(), 1u);                   // itself only
    // The model on the masked grid: no energy or mass from the hole, and no repulsion with it.
    // (The paper's convention: every other particle a full patch; the convergent one's dual
    // cells are tested in tests/testers/test_discretization.cpp.)
    model::ModelOptions paper;
    paper.discretization = model::Discretization::PAPER;
    const model::ClothModel m(
        kes::FittedFabric{"t", kCottonW / units::kMgPerCm2ToKgPerM2, Curves::fitted().warp, Curves::fitted().weft, Curves::fitted().shear},
        grid, paper, active);
    EXPECT_EQ(m.mass(hole), 0.0);
    EXPECT_NEAR(m.mass(0), kCottonW * kSigma * kSigma, 1e-18);
    Positions x = model::flat_grid(grid, Vec3(0, 0, 0.5));
    x[hole] = x[grid.index(1, 1)];  // where an active particle is: ignored
    EXPECT_TRUE(m.close_pairs(x).empty());
    EXPECT_NEAR(m.evaluate(x).gravity, 24 * m.mass(0) * units::kStandardGravity * 0.5, 1e-15);
}

}  // namespace
}  // namespace woven::test
