// ClothModel as a whole: the flat rest state, rigid-motion invariance, the spatial hash of
// close_pairs, the grid/thread convention, make_cloth_model's derived quantities, singular states.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "model/model_test_support.hpp"
#include "woven/common/error.hpp"
#include "woven/model/cloth_model.hpp"

namespace woven::test {
namespace {

using model::ClothModel;
using model::EnergyTerms;
using model::Grid;

constexpr double kPi = std::numbers::pi;

class FlatGrid : public testing::TestWithParam<double> {};  // yaw

TEST_P(FlatGrid, HasOnlyGravityEnergyAndGradient)
{
    const Grid grid{7, 6, 0.02};
    const ClothModel m = make_model(grid, Terms::all());
    const double z = 0.5;
    const Positions x = model::flat_grid(grid, Vec3(0.2, -0.1, z), GetParam());
    const EnergyTerms e = m.evaluate(x);
    // Zero up to rounding when yawed: c = cos(angle) carries ~1e-16 of rounding, which is
    // B'(-1) * 1e-16 ~ 1e-20 J of bending; bounded here by 1e-17 J (a 1-degree bend of one thread
    // costs ~1e-9 J). |r - sigma| ~ 1e-18 m gives S, R ~ C0 1e-80.
    EXPECT_LE(e.repulsion, 1e-17);
    EXPECT_LE(e.stretch, 1e-17);
    EXPECT_LE(e.bending_warp, 1e-17);
    EXPECT_LE(e.bending_weft, 1e-17);
    EXPECT_LE(e.trellis, 1e-17);
    if (GetParam() == 0.0) {  // axis-aligned: exactly straight threads and right angles
        EXPECT_EQ(e.bending_warp, 0.0);
        EXPECT_EQ(e.bending_weft, 0.0);
        EXPECT_EQ(e.trellis, 0.0);
    }
    // Gravity (Eq. 6): sum m g z, m = W sigma^2 = 0.15 kg/m^2 * 4e-4 m^2 = 6e-5 kg.
    const double mg = kCottonW * 0.02 * 0.02 * units::kStandardGravity;
    EXPECT_NEAR(e.gravity, grid.size() * mg * z, 1e-12 * grid.size() * mg * z);
    // The gradient is gravity's alone: exactly when axis-aligned; when yawed up to the rounding
    // of the angles (~1e-15 rad) times the trellis stiffness T''(0) ~ 0.04 J/rad^2 over 4 cm, i.e.
    // ~1e-15 N ~ 2e-12 m g: bounded by 1e-10 m g.
    const double tol = GetParam() == 0.0 ? 1e-14 * mg : 1e-10 * mg;
    const Eigen::VectorXd g = m.gradient(x);
    for (int k = 0; k < grid.size(); ++k) {
        EXPECT_NEAR(g[3 * k + 0], 0.0, tol) << k;
        EXPECT_NEAR(g[3 * k + 1], 0.0, tol) << k;
        EXPECT_NEAR(g[3 * k + 2], mg, tol) << k;
    }
}
INSTANTIATE_TEST_SUITE_P(Yaw, FlatGrid, testing::Values(0.0, 0.3, kPi / 4, 2.0));

TEST(HandValues, GravityOfOneParticle)
{
    // m g z = (0.15 kg/m^2 * (0.02 m)^2) * 9.80665 m/s^2 * 0.5 m = 6e-5 * 9.80665 * 0.5 = 2.941995e-4 J.
    const Grid grid{1, 1, 0.02};
    const ClothModel m = make_model(grid, Terms::all());
    EXPECT_NEAR(m.evaluate({Vec3(1, 2, 0.5)}).gravity, 2.941995e-4, 2.941995e-4 * 1e-12);
    EXPECT_NEAR(m.evaluate({Vec3(1, 2, 0.5)}).total(), 2.941995e-4, 2.941995e-4 * 1e-12);
}

class RigidMotion : public testing::TestWithParam<unsigned> {};

TEST_P(RigidMotion, LeavesInternalEnergiesUnchanged)
{
    const Grid grid{6, 5, 0.02};
    const ClothModel m = make_model(grid, Terms::all());
    const unsigned seed = GetParam();
    const Positions x = perturbed_grid(grid, seed, 0.15, seed % 2 ? 0.75 : 1.0);
    const EnergyTerms e = m.evaluate(x);
    ASSERT_GT(e.stretch + e.repulsion, 0.0);
    ASSERT_GT(e.bending_warp, 0.0);
    ASSERT_GT(e.bending_weft, 0.0);
    ASSERT_GT(e.trellis, 0.0);
    auto same = [](double a, double b, const char* what) { EXPECT_NEAR(a, b, 1e-12 * std::abs(b)) << what; };

    // Any rotation and translation: all terms but gravity.
    const Mat3 Q = random_rotation(seed + 77);
    const Vec3 t(0.13, -0.27, 0.05);
    Positions y(x.size());
    for (size_t k = 0; k < x.size(); ++k) y[k] = Q * x[k] + t;
    const EnergyTerms f = m.evaluate(y);
    same(f.repulsion, e.repulsion, "repulsion");
    same(f.stretch, e.stretch, "stretch");
    same(f.bending_warp, e.bending_warp, "bending_warp");
    same(f.bending_weft, e.bending_weft, "bending_weft");
    same(f.trellis, e.trellis, "trellis");

    // A rotation about the vertical and a horizontal translation: gravity too.
    const Mat3 Z = Eigen::AngleAxisd(0.7 + seed, Vec3::UnitZ()).toRotationMatrix();
    for (size_t k = 0; k < x.size(); ++k) y[k] = Z * x[k] + Vec3(-0.3, 0.2, 0.0);
    const EnergyTerms h = m.evaluate(y);
    same(h.gravity, e.gravity, "gravity");
    same(h.total(), e.total(), "total");
    // Lifting by dz adds n m g dz.
    for (size_t k = 0; k < x.size(); ++k) y[k] = x[k] + Vec3(0, 0, 0.1);
    EXPECT_NEAR(m.evaluate(y).gravity - e.gravity, grid.size() * m.particle_mass() * m.gravity() * 0.1, 1e-12);

    // The gradient rotates with the cloth and sums to the total weight.
    for (size_t k = 0; k < x.size(); ++k) y[k] = Q * x[k] + t;
    const Eigen::VectorXd gx = make_model(grid, {true, true, true, true, false}).gradient(x);
    const Eigen::VectorXd gy = make_model(grid, {true, true, true, true, false}).gradient(y);
    Vec3 sum = Vec3::Zero();
    for (int k = 0; k < grid.size(); ++k) {
        EXPECT_LE((Q * gx.segment<3>(3 * k) - gy.segment<3>(3 * k)).norm(), 1e-9 * gx.cwiseAbs().maxCoeff()) << k;
        sum += gx.segment<3>(3 * k);
    }
    EXPECT_LE(sum.norm(), 1e-10 * gx.cwiseAbs().maxCoeff());  // internal forces balance
}
INSTANTIATE_TEST_SUITE_P(Seeds, RigidMotion, testing::Range(1u, 7u));

std::vector<model::Stencil<2>> brute_force_pairs(const Positions& x, double sigma)
{
    std::vector<model::Stencil<2>> p;
    for (int i = 0; i < static_cast<int>(x.size()); ++i)
        for (int j = i + 1; j < static_cast<int>(x.size()); ++j)
            if ((x[i] - x[j]).squaredNorm() < sigma * sigma) p.push_back({i, j});
    return p;
}

struct CrumpleCase {
    unsigned seed;
    int n;
    double box;  ///< positions uniform in a cube of this side, in sigma
    Vec3 offset;
};
class ClosePairs : public testing::TestWithParam<CrumpleCase> {};

TEST_P(ClosePairs, EqualBruteForce)
{
    const auto [seed, n, box, offset] = GetParam();
    const Grid grid{n, n, 0.02};
    const ClothModel m = make_model(grid, Terms::all());
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, box * grid.sigma);
    Positions x(grid.size());
    for (Vec3& p : x) p = offset + Vec3(u(rng), u(rng), u(rng));
    // A few particles exactly on cell boundaries and exact duplicates of distance sigma apart.
    x[0] = Vec3(0, 0, 0) + offset;
    x[1] = Vec3(grid.sigma, 0, 0) + offset;               // exactly sigma: not a pair (r < sigma)
    x[2] = Vec3(grid.sigma * 0.999999, 0, 0) + offset;    // just inside
    const auto expected = brute_force_pairs(x, grid.sigma);
    const auto got = m.close_pairs(x);
    EXPECT_EQ(got, expected);
    EXPECT_GT(expected.size(), static_cast<size_t>(n));
    // A larger search radius (the paper solver's margin) finds more pairs, again exactly.
    const auto wider = brute_force_pairs(x, 1.7 * grid.sigma);
    EXPECT_EQ(m.close_pairs(x, 1.7 * grid.sigma), wider);
    EXPECT_GT(wider.size(), expected.size());
}
INSTANTIATE_TEST_SUITE_P(Crumpled, ClosePairs,
                         testing::Values(CrumpleCase{1, 6, 3.0, Vec3(0.1, 0.2, 0.3)}, CrumpleCase{2, 6, 2.0, Vec3(-0.5, -0.3, -0.01)},
                                         CrumpleCase{3, 12, 5.0, Vec3(-0.03, 0.01, 0.0)}, CrumpleCase{4, 20, 8.0, Vec3(-1.0, -1.0, -1.0)},
                                         CrumpleCase{5, 15, 1.0, Vec3(0.0, 0.0, 0.0)}, CrumpleCase{6, 10, 4.0, Vec3(250.0, -130.0, 7.0)}));

TEST(ClosePairs, OfAPerturbedGridEqualBruteForce)
{
    const Grid grid{12, 10, 0.02};
    const ClothModel m = make_model(grid, Terms::all());
    for (unsigned seed = 1; seed <= 5; ++seed) {
        const Positions x = perturbed_grid(grid, seed, 0.2, 0.8);
        EXPECT_EQ(m.close_pairs(x), brute_force_pairs(x, grid.sigma));
    }
}

TEST(Convention, WeftBendsAlongIWarpAlongJ)
{
    // weft threads run along i, warp along j (MODEL-NOTES). A bent 3 x 1 row is weft bending and
    // uses the weft curve; a bent 1 x 3 column is warp bending with the warp curve.
    const Curves curves = Curves::fitted();
    const double theta = 2.0, s = 0.02;
    const Positions x = {Vec3(s, 0, 0), Vec3::Zero(), Vec3(s * std::cos(theta), s * std::sin(theta), 0)};
    const ClothModel row = make_model(Grid{3, 1, s}, Terms::all(), curves);
    const EnergyTerms er = row.evaluate(x);
    EXPECT_EQ(er.bending_warp, 0.0);
    EXPECT_NEAR(er.bending_weft, row.bending_weft().of_angle(theta), 1e-12 * er.bending_weft);
    const ClothModel column = make_model(Grid{1, 3, s}, Terms::all(), curves);
    const EnergyTerms ec = column.evaluate(x);
    EXPECT_EQ(ec.bending_weft, 0.0);
    EXPECT_NEAR(ec.bending_warp, column.bending_warp().of_angle(theta), 1e-12 * ec.bending_warp);
    EXPECT_GT(ec.bending_weft + er.bending_weft, 1.5 * (ec.bending_warp + er.bending_warp));  // cotton weft stiffer
}

TEST(Convention, TrellisAngleIsBetweenThreadLinesThroughNeighbours)
{
    // 3 x 3 grid sheared by phi: the angle between (i-1,j)->(i+1,j) and (i,j-1)->(i,j+1) is 90 deg + phi;
    // the centre particle does not enter.
    const double s = 0.02;
    const Grid grid{3, 3, s};
    const ClothModel m = make_model(grid, Terms::all());
    for (double phi : {0.05, -0.2, 0.4}) {
        const Vec3 e1 = Vec3::UnitX(), w(std::cos(kPi / 2 + phi), std::sin(kPi / 2 + phi), 0);
        Positions x(9);
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) x[grid.index(i, j)] = s * ((i - 1) * e1 + (j - 1) * w);
        const double t = m.evaluate(x).trellis;
        EXPECT_NEAR(t, m.trellis().of_angle(phi).value, 1e-12 * t);
        x[grid.index(1, 1)] += Vec3(0.003, -0.002, 0.004);  // moving the centre changes no trellis angle
        EXPECT_NEAR(m.evaluate(x).trellis, t, 1e-12 * t);
    }
}

TEST(MakeClothModel, DerivesMassC0AndCurves)
{
    kes::FabricData f;
    f.name = "cotton-like";
    f.source = "test";
    f.areal_density_mg_cm2 = 15.0;
    f.bending_warp.curve = kes::synthesize_bending_curve(cotton_warp());
    f.bending_weft.curve = kes::synthesize_bending_curve(cotton_weft());
    f.shear.curve = kes::synthesize_shear_curve(cotton_shear());
    const Grid grid{51, 51, 0.02};
    const ClothModel m = model::make_cloth_model(f, grid, model::ModelOptions{});
    EXPECT_NEAR(m.particle_mass(), 0.15 * 0.02 * 0.02, 1e-18);  // W sigma^2
    EXPECT_NEAR(m.spacing().C0, 5883.99, 5883.99 * 1e-12);       // hanging length 0.5 m, 1 % strain
    EXPECT_EQ(m.spacing().sigma, 0.02);
    EXPECT_EQ(m.gravity(), units::kStandardGravity);
    EXPECT_NEAR(m.bending_weft().sigma_cm(), 2.0, 1e-14);
    EXPECT_NEAR(m.bending_warp().moment().line().c1, 0.06, 0.02 * 0.06);
    EXPECT_NEAR(m.bending_weft().moment().line().c1, 0.15, 0.02 * 0.15);
    model::ModelOptions o;
    o.C0 = 123.0;
    EXPECT_EQ(model::make_cloth_model(f, grid, o).spacing().C0, 123.0);
}

TEST(Singular, InfiniteEnergiesAreReportedNotSentToTheSink)
{
    const double s = 0.02;
    DenseSink sink(3);
    // Two particles at the same place: repulsion infinite.
    {
        const ClothModel m = make_model(Grid{3, 1, s}, Terms::all());
        const Positions x = {Vec3(0, 0, 0), Vec3(s, 0, 0), Vec3(0, 0, 0)};
        const EnergyTerms e = m.evaluate(x, model::Derivatives::GRADIENT, sink);
        EXPECT_TRUE(std::isinf(e.repulsion));
        EXPECT_TRUE(std::isinf(e.bending_weft));  // and a thread folded to theta = 0
        EXPECT_TRUE(sink.g.allFinite());
    }
    // Trellis past 1.05 rad.
    {
        const Grid grid{3, 3, s};
        const ClothModel m = make_model(grid, Terms::all());
        const double phi = 1.1;
        const Vec3 e1 = Vec3::UnitX(), w(std::cos(kPi / 2 + phi), std::sin(kPi / 2 + phi), 0);
        Positions x(9);
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 3; ++i) x[grid.index(i, j)] = s * ((i - 1) * e1 + (j - 1) * w);
        DenseSink sink9(9);
        const EnergyTerms e = m.evaluate(x, model::Derivatives::HESSIAN, sink9);
        EXPECT_TRUE(std::isinf(e.trellis));
        EXPECT_TRUE(sink9.g.allFinite());
        EXPECT_TRUE(sink9.H.allFinite());
    }
}

// ---------------------------------------------------------------------------------------------
// Bias bending (model::BiasBending::FABRIC, beyond the paper).

/// A convergent model of linear thread curves B_warp, B_weft (gf.cm^2/cm) with bias bending.
ClothModel bias_model(const Grid& grid, double B_warp, double B_weft, std::optional<double> bias_B)
{
    kes::FittedFabric f;
    f.name = "bias test";
    f.areal_density_mg_cm2 = 15;
    f.bending_warp = smooth_curve(B_warp, 0, 2.5);
    f.bending_weft = smooth_curve(B_weft, 0, 2.5);
    f.shear = zero_curve(8.0);
    f.bias_B = bias_B;
    model::ModelOptions o;
    o.bending_form = model::BendingForm::WORK;
    o.gravity = 0;
    o.bias_bending = model::BiasBending::FABRIC;
    return ClothModel(f, grid, o);
}

TEST(BiasBending, RigidityFromMeasurementOrHubersEstimate)
{
    // Huber: (B1 + B2) / 4 + sqrt(B1 B2) / 2; a balanced fabric is isotropic (B_45 = B).
    EXPECT_DOUBLE_EQ(model::bias_rigidity_estimate(0.1, 0.1), 0.1);
    EXPECT_NEAR(model::bias_rigidity_estimate(0.04, 0.16), 0.05 + 0.04, 1e-15);
    const Grid grid{5, 5, 0.01};
    const ClothModel estimated = bias_model(grid, 0.04, 0.16, std::nullopt);
    const ClothModel measured = bias_model(grid, 0.04, 0.16, 0.12);
    // T = 4 (B_45 - (B1 + B2) / 4) gf.cm^2/cm, in N m: x gf (N) / 100.
    const double gf_cm = units::newton_per_gram_force(units::GramForce::PAPER) / units::kMToCm;
    EXPECT_NEAR(estimated.twist_rigidity(), 4 * (0.09 - 0.05) * gf_cm, 1e-12 * gf_cm);
    EXPECT_NEAR(measured.twist_rigidity(), 4 * (0.12 - 0.05) * gf_cm, 1e-12 * gf_cm);
    EXPECT_EQ(static_cast<int>(measured.stencils().cells.size()), 16);
    // Below the threads' own bias rigidity: refused, naming the field.
    try {
        bias_model(grid, 0.04, 0.16, 0.04);
        ADD_FAILURE() << "a bias B below (B1 + B2) / 4 was accepted";
    } catch (const InputError& e) {
        EXPECT_EQ(e.field(), "bending.bias.B");
    }
}

TEST(BiasBending, TheModelsPolarDiagramIsTheOrthotropicPlates)
{
    // A cylindrical bend of curvature k whose generators make angle alpha with the v thread (the
    // warp) stores, per unit area, k^2 B(alpha) / 2 with B(alpha) = B_warp s^4 + B_weft c^4 +
    // 2 H c^2 s^2, H = 2 B_45 - (B_warp + B_weft) / 2 (B_45 at 45 degrees): each thread sees the
    // normal curvature k s^2 (warp) or k c^2 (weft), each cell the twist k c s. Each stencil
    // stands for its weight's share of sigma^2 (the convergent discretisation's quadrature).
    const Grid grid{21, 21, 0.005};
    const double B_warp = 0.05, B_weft = 0.12, B_45 = 0.11;
    const ClothModel m = bias_model(grid, B_warp, B_weft, B_45);
    const double gf_cm = units::newton_per_gram_force(units::GramForce::PAPER) / units::kMToCm;
    const double k = 2.0;  // 1/m: k sigma = 0.01
    double w_warp = 0, w_weft = 0;
    for (double w : m.stencils().warp_weights) w_warp += w;
    for (double w : m.stencils().weft_weights) w_weft += w;
    const double cells = static_cast<double>(m.stencils().cells.size());
    const double H = 2 * B_45 - 0.5 * (B_warp + B_weft);
    for (double alpha_deg : {0.0, 22.5, 45.0, 60.0, 90.0}) {
        const double a = alpha_deg * std::numbers::pi / 180, c = std::cos(a), s = std::sin(a);
        Positions x(grid.size());
        for (int j = 0; j < grid.nv; ++j)
            for (int i = 0; i < grid.nu; ++i) {
                const double u = (i - 0.5 * (grid.nu - 1)) * grid.sigma, v = (j - 0.5 * (grid.nv - 1)) * grid.sigma;
                const double across = c * u - s * v, along = s * u + c * v;  // across and along the generators
                const double phi = k * across;
                const Vec3 p(std::sin(phi) / k, 0, (1 - std::cos(phi)) / k);  // the arc: arclength = across
                x[grid.index(i, j)] = Vec3(c * p.x() + s * along, -s * p.x() + c * along, p.z());
            }
        const EnergyTerms e = m.evaluate(x);
        const double area = grid.sigma * grid.sigma, half_k2 = 0.5 * k * k * gf_cm * area;
        const double warp = half_k2 * B_warp * std::pow(s, 4) * w_warp, weft = half_k2 * B_weft * std::pow(c, 4) * w_weft;
        const double twist = half_k2 * 2 * H * c * c * s * s * cells;
        const double scale = half_k2 * B_45 * cells;
        EXPECT_NEAR(e.bending_warp, warp, 1e-3 * scale) << "alpha " << alpha_deg << " deg";
        EXPECT_NEAR(e.bending_weft, weft, 1e-3 * scale) << "alpha " << alpha_deg << " deg";
        EXPECT_NEAR(e.twist, twist, 1e-3 * scale) << "alpha " << alpha_deg << " deg";
    }
}

}  // namespace
}  // namespace woven::test
