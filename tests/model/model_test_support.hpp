#pragma once
// Test-only helpers of the model tests: fabrics and isolated-term models, random grids, a sink
// that assembles dense gradients/Hessians and keeps every local stencil matrix, and central
// finite differences.
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "woven/common/types.hpp"
#include "woven/common/units.hpp"
#include "woven/kes/curve.hpp"
#include "woven/kes/fabric.hpp"
#include "woven/kes/fit.hpp"
#include "woven/model/cloth_model.hpp"
#include "woven/model/energy_functions.hpp"

namespace woven::test {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

/// y = c1 x + c2 x^2 on [0, inf): one smooth segment (no junctions), `x_max` the data range.
inline kes::CurveFit smooth_curve(double c1, double c2, double x_max)
{
    return kes::CurveFit({kes::Segment{0, kInf, 0, c1, c2}}, x_max);
}

/// A curve that is identically zero: switches a bending or trellis term off.
inline kes::CurveFit zero_curve(double x_max) { return smooth_curve(0, 0, x_max); }

/// Cotton-like KES summary values (within KES-DATA ranges; weft bending stiffer as in the
/// paper's cotton), W = 15 mg/cm^2.
inline constexpr double kCottonW = 0.15;  // kg/m^2
inline kes::BendingSummary cotton_warp() { return {0.06, 0.04}; }
inline kes::BendingSummary cotton_weft() { return {0.15, 0.08}; }
inline kes::ShearSummary cotton_shear() { return {1.5, 2.0, 3.0}; }

inline kes::CurveFit fitted_bending(const kes::BendingSummary& s)
{
    return kes::fit_first_stage(kes::synthesize_bending_curve(s), kes::bending_fit_options(), "test bending");
}
inline kes::CurveFit fitted_shear(const kes::ShearSummary& s)
{
    return kes::fit_first_stage(kes::synthesize_shear_curve(s), kes::shear_fit_options(), "test shear");
}

/// Which terms of Eq. (1) a test model has switched on.
struct Terms {
    bool spacing = false, warp = false, weft = false, trellis = false, gravity = false;
    static Terms all() { return {true, true, true, true, true}; }
};

/// The curves a test model uses when a term is on.
struct Curves {
    kes::CurveFit warp, weft, shear;
    /// The fitted cotton-like curves (several quadratic segments, C1 junctions).
    static Curves fitted() { return {fitted_bending(cotton_warp()), fitted_bending(cotton_weft()), fitted_shear(cotton_shear())}; }
    /// Single smooth segments (no junctions): for second-derivative checks. Shear data range 30
    /// degrees so that phi_e is far from the random configurations.
    static Curves smooth() { return {smooth_curve(0.06, 0.01, 2.5), smooth_curve(0.15, 0.03, 2.5), smooth_curve(1.5, 0.02, 30.0)}; }
};

inline double cotton_C0(double sigma) { return model::choose_C0(kCottonW, units::kStandardGravity, sigma, 0.5); }

/// A model on `grid` with only the terms in `on` (bending and trellis off: zero curves; gravity
/// off: g = 0, and then C0 is cotton_C0 unless given). Spacing is always on. `twist`: the
/// convergent discretisation with bias bending (the twist of the cells, Huber's estimate).
inline model::ClothModel make_model(const model::Grid& grid, Terms on, const Curves& curves = Curves::fitted(), double C0 = -1,
                                    model::BendingForm form = model::BendingForm::SECANT, bool twist = false)
{
    EXPECT_TRUE(on.spacing) << "the spacing terms cannot be switched off";
    kes::FittedFabric f;
    f.name = "test";
    f.areal_density_mg_cm2 = kCottonW / units::kMgPerCm2ToKgPerM2;
    f.bending_warp = on.warp ? curves.warp : zero_curve(2.5);
    f.bending_weft = on.weft ? curves.weft : zero_curve(2.5);
    f.shear = on.trellis ? curves.shear : zero_curve(8.0);
    model::ModelOptions o;
    // These tests check the paper's per-stencil terms at full weight; the convergent
    // discretisation's weights and masses are tested in tests/testers/test_discretization.cpp.
    o.discretization = model::Discretization::PAPER;
    o.bending_form = form;
    o.gram_force = units::GramForce::PAPER;
    o.gravity = on.gravity ? units::kStandardGravity : 0.0;
    o.C0 = C0 > 0 ? C0 : cotton_C0(grid.sigma);
    if (twist) {
        o.discretization = model::Discretization::CONVERGENT;
        o.bias_bending = model::BiasBending::FABRIC;
    }
    return model::ClothModel(f, grid, o);
}

/// The flat grid at height z0, then spacing scaled by `squeeze`, then each coordinate moved by a
/// normal deviate of `noise * sigma` (fixed seed): out-of-plane included.
inline Positions perturbed_grid(const model::Grid& grid, unsigned seed, double noise, double squeeze = 1.0, double z0 = 0.3)
{
    Positions x = model::flat_grid(grid, Vec3(0.1, -0.05, z0), 0.3);
    const Vec3 c(0.1, -0.05, z0);
    std::mt19937 rng(seed);
    std::normal_distribution<double> n(0.0, noise * grid.sigma);
    for (Vec3& p : x) p = c + squeeze * (p - c) + Vec3(n(rng), n(rng), n(rng));
    return x;
}

/// A random rotation (uniform axis, angle) from a seed.
inline Mat3 random_rotation(unsigned seed)
{
    std::mt19937 rng(seed);
    std::normal_distribution<double> n(0.0, 1.0);
    std::uniform_real_distribution<double> u(0.0, 2.0 * 3.141592653589793);
    const Vec3 axis = Vec3(n(rng), n(rng), n(rng)).normalized();
    return Eigen::AngleAxisd(u(rng), axis).toRotationMatrix();
}

/// One local contribution as sent to the sink.
struct Stencil {
    model::Term term;
    std::vector<int> ids;
    Eigen::VectorXd gradient;
    Eigen::MatrixXd hessian;  ///< empty when none was sent
};

/// Assembles the dense gradient and Hessian and keeps every stencil (a model::LocalSink).
class DenseSink {
public:
    explicit DenseSink(int n) : g(Eigen::VectorXd::Zero(3 * n)), H(Eigen::MatrixXd::Zero(3 * n, 3 * n)) { }
    template <int N> void add(model::Term term, const model::Stencil<N>& ids, const model::Local<N>& local, bool with_hessian)
    {
        Stencil s{term, std::vector<int>(ids.begin(), ids.end()), local.gradient, Eigen::MatrixXd()};
        if (with_hessian) s.hessian = local.hessian;
        model::add_local_gradient<N>(ids, local.gradient, g);
        if (with_hessian)
            for (int k = 0; k < N; ++k)
                for (int l = 0; l < N; ++l) H.block<3, 3>(3 * ids[k], 3 * ids[l]) += local.hessian.template block<3, 3>(3 * k, 3 * l);
        stencils.push_back(std::move(s));
    }
    Eigen::VectorXd g;
    Eigen::MatrixXd H;
    std::vector<Stencil> stencils;
};

inline Eigen::VectorXd model_gradient(const model::ClothModel& m, const Positions& x)
{
    DenseSink sink(static_cast<int>(x.size()));
    m.evaluate(x, model::Derivatives::GRADIENT, sink);
    return sink.g;
}

inline Eigen::MatrixXd model_hessian(const model::ClothModel& m, const Positions& x, model::Derivatives what = model::Derivatives::HESSIAN)
{
    DenseSink sink(static_cast<int>(x.size()));
    m.evaluate(x, what, sink);
    return sink.H;
}

/// Central differences of the total energy, step h (m).
inline Eigen::VectorXd fd_gradient(const model::ClothModel& m, Positions x, double h)
{
    Eigen::VectorXd g(3 * x.size());
    for (size_t k = 0; k < x.size(); ++k)
        for (int c = 0; c < 3; ++c) {
            const double x0 = x[k][c];
            x[k][c] = x0 + h;
            const double ep = m.energy(x);
            x[k][c] = x0 - h;
            const double em = m.energy(x);
            x[k][c] = x0;
            g[3 * k + c] = (ep - em) / (2.0 * h);
        }
    return g;
}

/// Central differences of the analytic gradient, step h (m).
inline Eigen::MatrixXd fd_hessian(const model::ClothModel& m, Positions x, double h)
{
    const int n = static_cast<int>(3 * x.size());
    Eigen::MatrixXd H(n, n);
    for (size_t k = 0; k < x.size(); ++k)
        for (int c = 0; c < 3; ++c) {
            const double x0 = x[k][c];
            x[k][c] = x0 + h;
            const Eigen::VectorXd gp = model_gradient(m, x);
            x[k][c] = x0 - h;
            const Eigen::VectorXd gm = model_gradient(m, x);
            x[k][c] = x0;
            H.col(3 * k + c) = (gp - gm) / (2.0 * h);
        }
    return H;
}

/// Largest componentwise |a - b| / max(|b|, floor), floor = floor_fraction * max|b|: the error
/// measure of the finite-difference checks (components far below the largest one are judged
/// against a fraction of it, not against themselves).
inline double max_relative_error(const Eigen::MatrixXd& fd, const Eigen::MatrixXd& exact, double floor_fraction = 1e-3)
{
    const double floor = std::max(floor_fraction * exact.cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
    double e = 0;
    for (Eigen::Index i = 0; i < fd.size(); ++i) e = std::max(e, std::abs(fd.data()[i] - exact.data()[i]) / std::max(std::abs(exact.data()[i]), floor));
    return e;
}

}  // namespace woven::test
