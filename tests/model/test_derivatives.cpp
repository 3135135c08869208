// Finite-difference checks of ClothModel::evaluate: the gradient of every term of Eq. (1) and of
// the total energy, the exact Hessian (Derivatives::HESSIAN), and the projected Hessian
// (Derivatives::PROJECTED: every local stencil matrix symmetric PSD, equal to the exact one for a
// straight thread). Random perturbed grids and near-degenerate single stencils, fixed seeds.
//
// Term isolation: the model runs with every term on; each stencil reaches the sink with its term
// (model::Term). The finite differences are taken of the matching EnergyTerms field. The terms
// on their own stencils are checked directly in test_terms.cpp.
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "model/model_test_support.hpp"
#include "woven/model/cloth_model.hpp"

namespace woven::test {
namespace {

using model::ClothModel;
using model::Derivatives;
using model::Grid;

enum class Term { REPULSION, STRETCH, BENDING_WARP, BENDING_WEFT, TRELLIS, GRAVITY, TWIST, TOTAL };
const char* term_name(Term t)
{
    switch (t) {
    case Term::REPULSION: return "repulsion";
    case Term::STRETCH: return "stretch";
    case Term::BENDING_WARP: return "bending_warp";
    case Term::BENDING_WEFT: return "bending_weft";
    case Term::TRELLIS: return "trellis";
    case Term::GRAVITY: return "gravity";
    case Term::TWIST: return "twist";
    case Term::TOTAL: return "total";
    }
    return "?";
}
const Term kTerms[] = {Term::REPULSION, Term::STRETCH, Term::BENDING_WARP, Term::BENDING_WEFT, Term::TRELLIS, Term::GRAVITY, Term::TWIST, Term::TOTAL};

double term_value(const model::EnergyTerms& e, Term t)
{
    switch (t) {
    case Term::REPULSION: return e.repulsion;
    case Term::STRETCH: return e.stretch;
    case Term::BENDING_WARP: return e.bending_warp;
    case Term::BENDING_WEFT: return e.bending_weft;
    case Term::TRELLIS: return e.trellis;
    case Term::GRAVITY: return e.gravity;
    case Term::TWIST: return e.twist;
    case Term::TOTAL: return e.total();
    }
    return 0;
}

Term term_of(const Stencil& s)
{
    switch (s.term) {
    case model::Term::GRAVITY: return Term::GRAVITY;
    case model::Term::STRETCH: return Term::STRETCH;
    case model::Term::REPULSION: return Term::REPULSION;
    case model::Term::BENDING_WARP: return Term::BENDING_WARP;
    case model::Term::BENDING_WEFT: return Term::BENDING_WEFT;
    case model::Term::TRELLIS: return Term::TRELLIS;
    case model::Term::TWIST: return Term::TWIST;
    }
    return Term::TOTAL;
}

/// The gradient and Hessian of one term (or the total), assembled from its stencils.
struct TermDerivatives {
    Eigen::VectorXd g;
    Eigen::MatrixXd H;
    std::vector<Stencil> stencils;
};
TermDerivatives term_derivatives(const ClothModel& m, const Positions& x, Term t, Derivatives what)
{
    DenseSink sink(static_cast<int>(x.size()));
    m.evaluate(x, what, sink);
    const int n = static_cast<int>(3 * x.size());
    TermDerivatives d{Eigen::VectorXd::Zero(n), Eigen::MatrixXd::Zero(n, n), {}};
    for (const Stencil& s : sink.stencils) {
        if (t != Term::TOTAL && term_of(s) != t) continue;
        const int k = static_cast<int>(s.ids.size());
        for (int a = 0; a < k; ++a) {
            d.g.segment<3>(3 * s.ids[a]) += s.gradient.segment<3>(3 * a);
            if (s.hessian.size())
                for (int b = 0; b < k; ++b) d.H.block<3, 3>(3 * s.ids[a], 3 * s.ids[b]) += s.hessian.block<3, 3>(3 * a, 3 * b);
        }
        d.stencils.push_back(s);
    }
    return d;
}

Eigen::VectorXd fd_term_gradient(const ClothModel& m, Positions x, Term t, double h)
{
    Eigen::VectorXd g(3 * x.size());
    for (size_t k = 0; k < x.size(); ++k)
        for (int c = 0; c < 3; ++c) {
            const double x0 = x[k][c];
            auto at = [&](double step) {
                x[k][c] = x0 + step;
                return term_value(m.evaluate(x), t);
            };
            // Fourth-order central difference (truncation ~ h^4): the pair terms vary as u^5 near
            // r = sigma, where a second-order difference is not accurate to 1e-6.
            g[3 * k + c] = (8.0 * (at(h) - at(-h)) - (at(2 * h) - at(-2 * h))) / (12.0 * h);
            x[k][c] = x0;
        }
    return g;
}

Eigen::MatrixXd fd_term_hessian(const ClothModel& m, Positions x, Term t, double h)
{
    const int n = static_cast<int>(3 * x.size());
    Eigen::MatrixXd H(n, n);
    for (size_t k = 0; k < x.size(); ++k)
        for (int c = 0; c < 3; ++c) {
            const double x0 = x[k][c];
            auto at = [&](double step) {
                x[k][c] = x0 + step;
                return term_derivatives(m, x, t, Derivatives::GRADIENT).g;
            };
            H.col(3 * k + c) = (8.0 * (at(h) - at(-h)) - (at(2 * h) - at(-2 * h))) / (12.0 * h);
            x[k][c] = x0;
        }
    return H;
}

constexpr double kGradientTolerance = 1e-6;  // relative, |g_fd - g| / max(|g|, 1e-3 max|g|)
constexpr double kHessianTolerance = 1e-5;   // relative, same measure on the Hessian entries
constexpr double kStepFraction = 1e-6;       // FD step = 1e-6 sigma

/// Bending angle of a stencil, accurate near pi (atan2, not acos of the cosine).
double bending_angle(const Stencil& s, const Positions& x)
{
    const Vec3 a = x[s.ids[0]] - x[s.ids[1]], b = x[s.ids[2]] - x[s.ids[1]];
    return std::atan2(a.cross(b).norm(), a.dot(b));
}

constexpr double kNearStraight = 1e-4;  // pi - theta below this: see check_near_straight

/// Near a straight thread the bending energy, a function of c = cos(theta), carries an absolute
/// rounding error ~ eps |dB/dc| (1 + c is ~theta_dev^2/2 and c is rounded), so a finite
/// difference of it cannot reach 1e-6 there. Instead the stencil gradient is checked against
/// its geometric form: |dE/dx0| = |dB/dc| sin(theta) / |a|, |dE/dx2| = |dB/dc| sin(theta) / |b|,
/// each perpendicular to its arm, and the three forces sum to zero. dB/dc is the function
/// checked by finite differences near c = -1 in test_energy_functions.cpp.
void check_near_straight(const model::BendingEnergy& energy, const Stencil& s, const Positions& x)
{
    const Vec3 a = x[s.ids[0]] - x[s.ids[1]], b = x[s.ids[2]] - x[s.ids[1]];
    const double theta = bending_angle(s, x);
    const double f1 = std::abs(energy.of_cosine(std::cos(theta)).d1);
    const Vec3 g0 = s.gradient.segment<3>(0), g1 = s.gradient.segment<3>(3), g2 = s.gradient.segment<3>(6);
    const double floor = 1e-14 * f1 / std::min(a.norm(), b.norm());  // rounding of grad c at theta = pi
    EXPECT_NEAR(g0.norm(), f1 * std::sin(theta) / a.norm(), 1e-6 * f1 * std::sin(theta) / a.norm() + floor);
    EXPECT_NEAR(g2.norm(), f1 * std::sin(theta) / b.norm(), 1e-6 * f1 * std::sin(theta) / b.norm() + floor);
    EXPECT_LE(std::abs(g0.dot(a.normalized())), floor);
    EXPECT_LE(std::abs(g2.dot(b.normalized())), floor);
    EXPECT_LE((g0 + g1 + g2).norm(), floor);
}

/// Trellis angle of a stencil (ids L R D U): the angle between u = xR - xL and v = xU - xD minus
/// 90 degrees.
double trellis_angle(const Stencil& s, const Positions& x)
{
    const Vec3 u = x[s.ids[1]] - x[s.ids[0]], v = x[s.ids[3]] - x[s.ids[2]];
    return -std::asin(u.normalized().dot(v.normalized()));
}

constexpr double kNearSquare = 1e-4;  // |phi| below this: see check_near_square

/// T is even with a |phi|^3 term (F has curvature at the origin), so it is C2 but not C3 at
/// phi = 0 and a finite difference whose step (~1e-6 rad) exceeds |phi| cannot reach 1e-6. The
/// stencil gradient is checked against its geometric form instead: |dE/dxR| = |T'(phi)| / |u|,
/// perpendicular to u, dE/dxL = -dE/dxR (and the same for D, U with v). T'(phi) is the function
/// checked by finite differences at small phi in test_energy_functions.cpp.
void check_near_square(const model::TrellisEnergy& energy, const Stencil& s, const Positions& x)
{
    const Vec3 u = x[s.ids[1]] - x[s.ids[0]], v = x[s.ids[3]] - x[s.ids[2]];
    const double phi = trellis_angle(s, x);
    const double t1 = std::abs(energy.of_angle(phi).d1), t2 = energy.of_angle(0.0).d2;
    const Vec3 gL = s.gradient.segment<3>(0), gR = s.gradient.segment<3>(3), gD = s.gradient.segment<3>(6), gU = s.gradient.segment<3>(9);
    const double floor = 1e-14 * t2 / std::min(u.norm(), v.norm());  // rounding of c at phi = 0
    EXPECT_NEAR(gR.norm(), t1 / u.norm(), 1e-6 * t1 / u.norm() + floor);
    EXPECT_NEAR(gU.norm(), t1 / v.norm(), 1e-6 * t1 / v.norm() + floor);
    EXPECT_LE(std::abs(gR.dot(u.normalized())), floor);
    EXPECT_LE(std::abs(gU.dot(v.normalized())), floor);
    EXPECT_LE((gL + gR).norm(), floor);
    EXPECT_LE((gD + gU).norm(), floor);
}

/// Every term's gradient and the total's against central differences.
void check_gradients(const ClothModel& m, const Positions& x, const std::string& where)
{
    const double h = kStepFraction * m.grid().sigma;
    const model::EnergyTerms e = m.evaluate(x);
    for (Term t : kTerms) {
        SCOPED_TRACE(where + " term " + term_name(t));
        const double value = term_value(e, t);
        ASSERT_TRUE(std::isfinite(value));
        const TermDerivatives d = term_derivatives(m, x, t, Derivatives::GRADIENT);
        if (!d.stencils.empty() && (t == Term::BENDING_WARP || t == Term::BENDING_WEFT)) {
            bool all_straight = true;
            for (const Stencil& st : d.stencils) all_straight = all_straight && std::numbers::pi - bending_angle(st, x) < kNearStraight;
            if (all_straight) {
                for (const Stencil& st : d.stencils) check_near_straight(t == Term::BENDING_WARP ? m.bending_warp() : m.bending_weft(), st, x);
                continue;
            }
        }
        if (!d.stencils.empty() && t == Term::TRELLIS) {
            bool all_square = true;
            for (const Stencil& st : d.stencils) all_square = all_square && std::abs(trellis_angle(st, x)) < kNearSquare;
            if (all_square) {
                for (const Stencil& st : d.stencils) check_near_square(m.trellis(), st, x);
                continue;
            }
        }
        if (value == 0.0) {  // an inactive term sends nothing (or zeros)
            EXPECT_EQ(d.g.cwiseAbs().maxCoeff(), 0.0);
            continue;
        }
        // Stencils of this term are found; the assembled gradient is non-trivial.
        ASSERT_GT(d.g.cwiseAbs().maxCoeff(), 0.0);
        const Eigen::VectorXd fd = fd_term_gradient(m, x, t, h);
        EXPECT_LE(max_relative_error(fd, d.g), kGradientTolerance) << "energy " << value << " J, max |g| " << d.g.cwiseAbs().maxCoeff();
    }
    // ClothModel::gradient is the same total.
    const Eigen::VectorXd g = m.gradient(x);
    EXPECT_LE(max_relative_error(g, term_derivatives(m, x, Term::TOTAL, Derivatives::GRADIENT).g, 0.0), 1e-14);
}

/// The exact Hessian of every term against central differences of its gradient; the exact
/// Hessian's gradient equals the GRADIENT mode's.
void check_hessians(const ClothModel& m, const Positions& x, const std::string& where)
{
    const double h = kStepFraction * m.grid().sigma;
    const model::EnergyTerms e = m.evaluate(x);
    for (Term t : kTerms) {
        if (t == Term::GRAVITY) continue;  // linear: zero Hessian, none sent
        SCOPED_TRACE(where + " term " + term_name(t));
        if (term_value(e, t) == 0.0) continue;
        const TermDerivatives d = term_derivatives(m, x, t, Derivatives::HESSIAN);
        const TermDerivatives dg = term_derivatives(m, x, t, Derivatives::GRADIENT);
        EXPECT_LE(max_relative_error(d.g, dg.g, 0.0), 1e-14);
        ASSERT_GT(d.H.cwiseAbs().maxCoeff(), 0.0);
        const Eigen::MatrixXd fd = fd_term_hessian(m, x, t, h);
        EXPECT_LE(max_relative_error(fd, d.H), kHessianTolerance) << "max |H| " << d.H.cwiseAbs().maxCoeff();
        EXPECT_LE((d.H - d.H.transpose()).cwiseAbs().maxCoeff(), 1e-12 * d.H.cwiseAbs().maxCoeff());
    }
}

/// Every stencil matrix of the PROJECTED mode symmetric and PSD; gradients as in GRADIENT mode.
void check_projected(const ClothModel& m, const Positions& x, const std::string& where)
{
    SCOPED_TRACE(where);
    const TermDerivatives p = term_derivatives(m, x, Term::TOTAL, Derivatives::PROJECTED);
    const TermDerivatives g = term_derivatives(m, x, Term::TOTAL, Derivatives::GRADIENT);
    EXPECT_LE(max_relative_error(p.g, g.g, 0.0), 1e-14);
    int matrices = 0;
    for (const Stencil& s : p.stencils) {
        if (s.ids.size() == 1) continue;  // gravity: linear, no Hessian
        ASSERT_EQ(s.hessian.rows(), static_cast<Eigen::Index>(3 * s.ids.size())) << "a stencil of " << s.ids.size() << " particles came without its Hessian";
        const double big = s.hessian.cwiseAbs().maxCoeff();
        EXPECT_LE((s.hessian - s.hessian.transpose()).cwiseAbs().maxCoeff(), 1e-12 * big);
        const Eigen::MatrixXd sym = 0.5 * (s.hessian + s.hessian.transpose());
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(sym, Eigen::EigenvaluesOnly);
        const double lo = es.eigenvalues().minCoeff(), hi = es.eigenvalues().cwiseAbs().maxCoeff();
        EXPECT_GE(lo, -1e-10 * hi) << term_name(term_of(s)) << " stencil, eigenvalues " << es.eigenvalues().transpose();
        ++matrices;
    }
    EXPECT_GT(matrices, 0);
}

// ---------------------------------------------------------------------------------------------
// Random perturbed 6 x 5 grids, sigma = 2 cm.

struct GridCase {
    unsigned seed;
    double noise;    ///< normal perturbation, fraction of sigma (in and out of plane)
    double squeeze;  ///< spacing factor before the perturbation (< 1: repulsion active)
};
std::string grid_case_name(const testing::TestParamInfo<GridCase>& info)
{
    return "seed" + std::to_string(info.param.seed) + "_noise" + std::to_string(static_cast<int>(info.param.noise * 100)) + "_squeeze" +
           std::to_string(static_cast<int>(info.param.squeeze * 100));
}

class RandomGrid : public testing::TestWithParam<GridCase> {
protected:
    const Grid grid{6, 5, 0.02};
    Positions positions() const { return perturbed_grid(grid, GetParam().seed, GetParam().noise, GetParam().squeeze); }
};

TEST_P(RandomGrid, GradientOfEveryTermMatchesFiniteDifferencesFittedCurves)
{
    check_gradients(make_model(grid, Terms::all(), Curves::fitted()), positions(), "fitted");
}

TEST_P(RandomGrid, GradientOfEveryTermMatchesFiniteDifferencesWorkForm)
{
    check_gradients(make_model(grid, Terms::all(), Curves::fitted(), -1, model::BendingForm::WORK), positions(), "work");
}

TEST_P(RandomGrid, ExactHessianMatchesFiniteDifferencesOfGradient)
{
    // Smooth single-segment curves: the fitted curves are only C1 at their junctions.
    check_hessians(make_model(grid, Terms::all(), Curves::smooth()), positions(), "smooth secant");
    check_hessians(make_model(grid, Terms::all(), Curves::smooth(), -1, model::BendingForm::WORK), positions(), "smooth work");
}

TEST_P(RandomGrid, TwistDerivativesMatchFiniteDifferences)
{
    // The convergent model with bias bending (the cells' twist, beyond the paper).
    check_gradients(make_model(grid, Terms::all(), Curves::fitted(), -1, model::BendingForm::WORK, true), positions(), "twist fitted");
    check_hessians(make_model(grid, Terms::all(), Curves::smooth(), -1, model::BendingForm::WORK, true), positions(), "twist smooth");
    check_projected(make_model(grid, Terms::all(), Curves::smooth(), -1, model::BendingForm::WORK, true), positions(), "twist smooth");
}

TEST_P(RandomGrid, ProjectedHessianStencilsAreSymmetricPositiveSemiDefinite)
{
    check_projected(make_model(grid, Terms::all(), Curves::fitted()), positions(), "fitted");
    check_projected(make_model(grid, Terms::all(), Curves::smooth(), -1, model::BendingForm::WORK), positions(), "smooth work");
}

TEST_P(RandomGrid, RepulsionIsActiveInCompressedGrids)
{
    // Guards the sweep: the compressed cases really exercise repulsion, the most compressed
    // also between particles that are not thread neighbours.
    const ClothModel m = make_model(grid, Terms::all());
    const Positions x = positions();
    const auto pairs = m.close_pairs(x);
    if (GetParam().squeeze <= 0.9) {
        EXPECT_GT(m.evaluate(x).repulsion, 0.0);
    }
    if (GetParam().squeeze <= 0.7) {
        int distant = 0;
        for (auto [p, q] : pairs) {
            const int di = std::abs(p % grid.nu - q % grid.nu), dj = std::abs(p / grid.nu - q / grid.nu);
            distant += di + dj > 1;
        }
        EXPECT_GT(distant, 0);
    }
    if (GetParam().squeeze >= 1.0 && GetParam().noise <= 0.1) {
        EXPECT_GT(m.evaluate(x).stretch, 0.0);
    }
}

std::vector<GridCase> grid_cases()
{
    std::vector<GridCase> c;
    for (unsigned s = 1; s <= 4; ++s) c.push_back({s, 0.10, 1.0});
    for (unsigned s = 11; s <= 14; ++s) c.push_back({s, 0.20, 1.0});
    for (unsigned s = 21; s <= 23; ++s) c.push_back({s, 0.15, 0.9});
    for (unsigned s = 31; s <= 33; ++s) c.push_back({s, 0.15, 0.65});
    for (unsigned s = 41; s <= 42; ++s) c.push_back({s, 0.10, 1.05});
    return c;
}
INSTANTIATE_TEST_SUITE_P(Sweep, RandomGrid, testing::ValuesIn(grid_cases()), grid_case_name);

// ---------------------------------------------------------------------------------------------
// Single near-degenerate stencils, in a random orientation.

enum class Kind { WEFT_BEND, WARP_BEND, TRELLIS, NEIGHBOUR_PAIR, DISTANT_PAIR };
struct StencilCase {
    std::string name;
    Kind kind;
    double value;             ///< theta (bending), phi (trellis) or r / sigma (pairs)
    bool from_phi_e = false;  ///< trellis: value is an offset from the model's phi_e
    unsigned seed = 7;
};

class NearDegenerateStencil : public testing::TestWithParam<StencilCase> {
protected:
    static constexpr double kSigma = 0.02;

    Grid grid() const
    {
        switch (GetParam().kind) {
        case Kind::WEFT_BEND: return {3, 1, kSigma};
        case Kind::WARP_BEND: return {1, 3, kSigma};
        case Kind::TRELLIS: return {3, 3, kSigma};
        case Kind::NEIGHBOUR_PAIR: return {2, 1, kSigma};
        case Kind::DISTANT_PAIR: return {3, 1, kSigma};
        }
        return {};
    }

    /// Positions in a local frame (e1, e2 in-plane), then rotated by a random rotation and moved.
    Positions positions(const ClothModel& m) const
    {
        const StencilCase& c = GetParam();
        std::mt19937 rng(c.seed);
        std::uniform_real_distribution<double> len(0.9 * kSigma, 1.1 * kSigma);
        const Vec3 e1 = Vec3::UnitX(), e2 = Vec3::UnitY();
        Positions x;
        switch (c.kind) {
        case Kind::WEFT_BEND:
        case Kind::WARP_BEND: {
            const double la = len(rng), lb = len(rng), th = c.value;
            x = {la * e1, Vec3::Zero(), lb * (std::cos(th) * e1 + std::sin(th) * e2)};
            break;
        }
        case Kind::TRELLIS: {
            const double phi = c.from_phi_e ? m.trellis().last_measured_angle() + c.value : c.value;
            const Vec3 w = std::cos(std::numbers::pi / 2 + phi) * e1 + std::sin(std::numbers::pi / 2 + phi) * e2;
            const Vec3 L = -len(rng) * e1, R = len(rng) * e1, D = -len(rng) * w, U = len(rng) * w;
            // (i, j) -> i + 3 j; every thread through the stencil is straight.
            x = {L + D, D, R + D, L, Vec3::Zero(), R, L + U, U, R + U};
            break;
        }
        case Kind::NEIGHBOUR_PAIR: x = {Vec3::Zero(), c.value * kSigma * Vec3(0.6, 0.0, 0.8)}; break;
        case Kind::DISTANT_PAIR:  // particles 0 and 2 at r, the middle one off to the side
            x = {Vec3::Zero(), 0.5 * c.value * kSigma * e1 + 0.9 * kSigma * e2, c.value * kSigma * e1};
            break;
        }
        const Mat3 Q = random_rotation(c.seed + 1000);
        // Near z = 0: the gravity energy m g z is then small, so the rounding of the total energy
        // (eps |E| / h) stays far below the tiny pair forces of the r ~ sigma cases.
        for (Vec3& p : x) p = Q * p + Vec3(0.3, -0.2, 0.01);
        return x;
    }
};

TEST_P(NearDegenerateStencil, GradientMatchesFiniteDifferences)
{
    for (const Curves& curves : {Curves::fitted(), Curves::smooth()}) {
        const ClothModel m = make_model(grid(), Terms::all(), curves);
        check_gradients(m, positions(m), GetParam().name);
    }
}

TEST_P(NearDegenerateStencil, ExactHessianMatchesFiniteDifferences)
{
    for (auto form : {model::BendingForm::SECANT, model::BendingForm::WORK}) {
        const ClothModel m = make_model(grid(), Terms::all(), Curves::smooth(), -1, form);
        check_hessians(m, positions(m), GetParam().name);
    }
}

TEST_P(NearDegenerateStencil, ProjectedHessianIsPositiveSemiDefinite)
{
    for (const Curves& curves : {Curves::fitted(), Curves::smooth()}) {
        const ClothModel m = make_model(grid(), Terms::all(), curves);
        check_projected(m, positions(m), GetParam().name);
    }
}

TEST_P(NearDegenerateStencil, TheStencilOfInterestIsActive)
{
    // Guards the sweep against vacuous cases: the term named by the case has energy.
    const ClothModel m = make_model(grid(), Terms::all());
    const model::EnergyTerms e = m.evaluate(positions(m));
    const StencilCase& c = GetParam();
    switch (c.kind) {
    case Kind::WEFT_BEND:
        EXPECT_EQ(e.bending_warp, 0.0);
        if (c.value < std::numbers::pi) {
            EXPECT_GT(e.bending_weft, 0.0);
        }
        break;
    case Kind::WARP_BEND:
        EXPECT_EQ(e.bending_weft, 0.0);
        if (c.value < std::numbers::pi) {
            EXPECT_GT(e.bending_warp, 0.0);
        }
        break;
    case Kind::TRELLIS:
        if (c.value != 0.0 || c.from_phi_e) {
            EXPECT_GT(e.trellis, 0.0);
        }
        break;
    case Kind::NEIGHBOUR_PAIR:
    case Kind::DISTANT_PAIR:
        if (c.value < 1.0) {
            EXPECT_GT(e.repulsion, 0.0);
        }
        if (c.kind == Kind::NEIGHBOUR_PAIR && c.value > 1.0) {
            EXPECT_GT(e.stretch, 0.0);
        }
        break;
    }
}

std::vector<StencilCase> stencil_cases()
{
    const double pi = std::numbers::pi;
    std::vector<StencilCase> c;
    const std::pair<const char*, double> thetas[] = {
        {"straight", pi}, {"pi_minus_1e6", pi - 1e-6}, {"pi_minus_1e3", pi - 1e-3}, {"t3", 3.0}, {"t2", 2.0}, {"half_pi", pi / 2},
        {"quarter_pi_above", pi / 4 + 1e-4}, {"quarter_pi_below", pi / 4 - 1e-4}, {"t05", 0.5}, {"t02", 0.2}, {"fold005", 0.05}};
    unsigned seed = 100;
    for (auto [n, t] : thetas) {
        c.push_back({std::string("weft_") + n, Kind::WEFT_BEND, t, false, seed++});
        c.push_back({std::string("warp_") + n, Kind::WARP_BEND, t, false, seed++});
    }
    const std::pair<const char*, double> phis[] = {{"zero", 0.0},  {"p1e7", 1e-7}, {"m005", -0.05}, {"p01", 0.1},
                                                   {"p03", 0.3},   {"m06", -0.6},  {"p10", 1.0},    {"m104", -1.04}};
    for (auto [n, p] : phis) c.push_back({std::string("trellis_") + n, Kind::TRELLIS, p, false, seed++});
    c.push_back({"trellis_phi_e_below", Kind::TRELLIS, -1e-4, true, seed++});
    c.push_back({"trellis_phi_e_above", Kind::TRELLIS, 1e-4, true, seed++});
    c.push_back({"trellis_phi_e_above_far", Kind::TRELLIS, 0.05, true, seed++});
    const std::pair<const char*, double> radii[] = {{"r1p001", 1.001}, {"r1p01", 1.01}, {"r1p2", 1.2}, {"r0p999", 0.999},
                                                    {"r0p99", 0.99},   {"r0p5", 0.5},   {"r0p1", 0.1}, {"r0p02", 0.02}};
    for (auto [n, r] : radii) c.push_back({std::string("pair_") + n, Kind::NEIGHBOUR_PAIR, r, false, seed++});
    for (double r : {0.999, 0.7, 0.3}) c.push_back({"distant_pair_r" + std::to_string(static_cast<int>(r * 1000)), Kind::DISTANT_PAIR, r, false, seed++});
    return c;
}
INSTANTIATE_TEST_SUITE_P(Sweep, NearDegenerateStencil, testing::ValuesIn(stencil_cases()),
                         [](const testing::TestParamInfo<StencilCase>& i) { return i.param.name; });

// ---------------------------------------------------------------------------------------------

/// The bending stencils of the PROJECTED and HESSIAN modes.
std::vector<Stencil> bending_stencils(const ClothModel& m, const Positions& x, Derivatives what)
{
    DenseSink sink(static_cast<int>(x.size()));
    m.evaluate(x, what, sink);
    std::vector<Stencil> out;
    for (const Stencil& s : sink.stencils)
        if (s.ids.size() == 3) out.push_back(s);
    return out;
}

TEST(ProjectedHessian, EqualsExactForStraightThreads)
{
    // Flat grid, no yaw: every thread is exactly straight (c = -1), where the bending Hessian is
    // f'(c) times the Hessian of c, which is J^T J (MODEL-NOTES; stencils.hpp).
    const Grid grid{5, 4, 0.02};
    for (const Curves& curves : {Curves::fitted(), Curves::smooth()}) {
        const ClothModel m = make_model(grid, Terms::all(), curves);
        const Positions x = model::flat_grid(grid, Vec3(0, 0, 0.4));
        const auto exact = bending_stencils(m, x, Derivatives::HESSIAN);
        const auto proj = bending_stencils(m, x, Derivatives::PROJECTED);
        ASSERT_EQ(exact.size(), proj.size());
        ASSERT_EQ(exact.size(), static_cast<size_t>(grid.nu * (grid.nv - 2) + grid.nv * (grid.nu - 2)));
        for (size_t k = 0; k < exact.size(); ++k) {
            ASSERT_EQ(exact[k].ids, proj[k].ids);
            const double big = exact[k].hessian.cwiseAbs().maxCoeff();
            ASSERT_GT(big, 0.0);  // straight threads are stiff in bending: f'(-1) = B-slope > 0
            EXPECT_LE((exact[k].hessian - proj[k].hessian).cwiseAbs().maxCoeff(), 1e-12 * big);
        }
    }
}

TEST(ProjectedHessian, NearlyEqualsExactForRotatedStraightThread)
{
    // A straight thread in a random orientation: c = -1 up to rounding, |a/|a| + b/|b|| ~ 1e-8,
    // so the two agree to about that (J^T J differs from c's Hessian by terms in that vector).
    const Grid grid{3, 1, 0.02};
    const ClothModel m = make_model(grid, Terms::all());
    for (unsigned seed = 1; seed <= 10; ++seed) {
        const Mat3 Q = random_rotation(seed);
        const Vec3 t = Q * Vec3::UnitX();
        const Positions x = {Vec3(0.1, 0.2, 0.3) - 0.021 * t, Vec3(0.1, 0.2, 0.3), Vec3(0.1, 0.2, 0.3) + 0.019 * t};
        const auto exact = bending_stencils(m, x, Derivatives::HESSIAN);
        const auto proj = bending_stencils(m, x, Derivatives::PROJECTED);
        ASSERT_EQ(exact.size(), 1u);
        const double big = exact[0].hessian.cwiseAbs().maxCoeff();
        EXPECT_LE((exact[0].hessian - proj[0].hessian).cwiseAbs().maxCoeff(), 1e-6 * big);
    }
}

TEST(ProjectedHessian, EqualsExactForConvexPairTerms)
{
    // Stretch (r > sigma): S'' > 0 and S'/r > 0, nothing to clamp: the projection is exact.
    const Grid grid{2, 1, 0.02};
    const ClothModel m = make_model(grid, Terms::all());
    const Positions x = {Vec3(0, 0, 0.2), Vec3(0.0212, 0.003, 0.2)};
    const Eigen::MatrixXd H = model_hessian(m, x, Derivatives::HESSIAN), P = model_hessian(m, x, Derivatives::PROJECTED);
    ASSERT_GT(H.cwiseAbs().maxCoeff(), 0.0);
    EXPECT_LE((H - P).cwiseAbs().maxCoeff(), 1e-14 * H.cwiseAbs().maxCoeff());
}

}  // namespace
}  // namespace woven::test
