// Per-particle fields of a drape (analysis/vertex_fields.hpp) against states whose strain,
// trellis angle, curvature, contact and residual force are known in closed form.
#include <cmath>
#include <memory>
#include <numbers>

#include <gtest/gtest.h>

#include "sim/sim_fixtures.hpp"
#include "woven/analysis/vertex_fields.hpp"
#include "woven/geometry/primitives.hpp"
#include "woven/sim/drape.hpp"

using namespace woven;

namespace {

constexpr int kNu = 7, kNv = 5;
constexpr double kSigma = 0.01;  // m

model::ClothModel cloth_model() { return model::make_cloth_model(test::cotton_like(), model::Grid{kNu, kNv, kSigma}, {}); }

/// Particle (i, j) at i a + j b (m): a uniform affine map of the flat grid.
Positions affine_grid(const Vec3& a, const Vec3& b)
{
    Positions x;
    for (int j = 0; j < kNv; ++j)
        for (int i = 0; i < kNu; ++i) x.push_back(i * a + j * b + Vec3(0, 0, 0.5));
    return x;
}

}  // namespace

TEST(VertexFields, UniformStretchGivesEachThreadItsStrainAndNoAngles)
{
    const auto model = cloth_model();
    const double ea = 0.03, eb = -0.01;  // weft (along i) stretched 3 %, warp (along j) compressed 1 %
    const Positions x = affine_grid(Vec3(kSigma * (1 + ea), 0, 0), Vec3(0, kSigma * (1 + eb), 0));
    const auto f = analysis::vertex_fields(model, geometry::ObstacleSet{}, x, 1e-3);
    ASSERT_EQ(f.strain_warp.size(), x.size());
    for (std::size_t p = 0; p < x.size(); ++p) {
        EXPECT_NEAR(f.strain_weft[p], ea, 1e-12) << p;
        EXPECT_NEAR(f.strain_warp[p], eb, 1e-12) << p;
        EXPECT_NEAR(f.trellis_angle[p], 0.0, 1e-12) << p;
        // Straight threads: K = sqrt(2 (1 + cos theta)) / sigma, cos theta = -1 to round-off.
        EXPECT_LT(f.curvature_warp[p], 1e-4) << p;
        EXPECT_LT(f.curvature_weft[p], 1e-4) << p;
        EXPECT_EQ(f.contact[p], 0.0) << p;
    }
}

TEST(VertexFields, UniformShearGivesTheTrellisAngleEverywhereEdgesIncluded)
{
    const auto model = cloth_model();
    const double gamma = 0.2;  // rad: the warp threads lean towards +x, the segments keep their length
    const Positions x = affine_grid(Vec3(kSigma, 0, 0), kSigma * Vec3(std::sin(gamma), std::cos(gamma), 0));
    const auto f = analysis::vertex_fields(model, geometry::ObstacleSet{}, x, 1e-3);
    // c = cos(angle(weft, warp)) = sin(gamma), phi = -asin(c) = -gamma; the default (convergent)
    // model has a crossing at every particle, one-sided at the edges and corners.
    for (std::size_t p = 0; p < x.size(); ++p) {
        EXPECT_NEAR(f.trellis_angle[p], -gamma, 1e-12) << p;
        EXPECT_NEAR(f.strain_warp[p], 0.0, 1e-12) << p;
        EXPECT_NEAR(f.strain_weft[p], 0.0, 1e-12) << p;
    }
}

TEST(VertexFields, WeftThreadsOnACylinderHaveItsCurvatureAndChordStrain)
{
    const auto model = cloth_model();
    const double R = 0.05;  // m: weft threads (along i) on a cylinder about the y axis, arc length sigma apart
    Positions x;
    for (int j = 0; j < kNv; ++j)
        for (int i = 0; i < kNu; ++i) {
            const double t = i * kSigma / R;
            x.push_back(Vec3(R * std::sin(t), j * kSigma, R * std::cos(t)));
        }
    const auto f = analysis::vertex_fields(model, geometry::ObstacleSet{}, x, 1e-3);
    // theta = pi - sigma/R at every inner particle: K = (2/sigma) cos(theta/2) = (2/sigma) sin(sigma/2R),
    // (1/R)(1 - (sigma/R)^2 / 24 + O((sigma/R)^4)); the chord 2R sin(sigma/2R) is the segment's length.
    const double K = 2.0 / kSigma * std::sin(kSigma / (2 * R));
    const double chord_strain = 2 * R / kSigma * std::sin(kSigma / (2 * R)) - 1;
    EXPECT_NEAR(K, (1 - (kSigma / R) * (kSigma / R) / 24) / R, 1e-5 / R);
    for (int j = 0; j < kNv; ++j)
        for (int i = 0; i < kNu; ++i) {
            const int p = i + kNu * j;
            const bool end = i == 0 || i == kNu - 1;
            EXPECT_NEAR(f.curvature_weft[p], end ? 0.0 : K, 1e-9) << i << " " << j;
            EXPECT_LT(f.curvature_warp[p], 1e-4) << i << " " << j;
            EXPECT_NEAR(f.strain_weft[p], chord_strain, 1e-12) << i << " " << j;
            EXPECT_NEAR(f.strain_warp[p], 0.0, 1e-12) << i << " " << j;
            EXPECT_NEAR(f.trellis_angle[p], 0.0, 1e-12) << i << " " << j;
        }
}

TEST(VertexFields, FlatClothAtRestCarriesItsWeightUnlessAPlaneHoldsIt)
{
    const auto model = cloth_model();
    const Positions x = affine_grid(Vec3(kSigma, 0, 0), Vec3(0, kSigma, 0));
    // In the air every force but gravity vanishes at rest: |F| = m_p g, each particle its own mass
    // (to the round-off of the spacings, which the stiff threads turn into ~1e-12 N).
    const double weight = model.particle_mass() * model.gravity();
    const auto free = analysis::vertex_fields(model, geometry::ObstacleSet{}, x, 1e-3, sim::residual_forces(model, geometry::ObstacleSet{}, x, 1e-3));
    for (std::size_t p = 0; p < x.size(); ++p) {
        EXPECT_NEAR(free.residual_force[p], model.mass(static_cast<int>(p)) * model.gravity(), 1e-6 * weight) << p;
        EXPECT_EQ(free.contact[p], 0.0);
    }
    // A floor 0.5 mm below, within the contact distance of 1 mm: it holds the weight.
    geometry::ObstacleSet floor;
    floor.add(std::make_unique<geometry::Plane>(Vec3(0, 0, 0.4995), Vec3(0, 0, 1)));
    const auto held = analysis::vertex_fields(model, floor, x, 1e-3, sim::residual_forces(model, floor, x, 1e-3));
    for (std::size_t p = 0; p < x.size(); ++p) {
        EXPECT_EQ(held.contact[p], 1.0) << p;
        EXPECT_NEAR(held.residual_force[p], 0.0, 1e-6 * weight) << p;
    }
    // The floor 2 mm below, past the contact distance: no contact, the weight is a residual again.
    geometry::ObstacleSet low;
    low.add(std::make_unique<geometry::Plane>(Vec3(0, 0, 0.498), Vec3(0, 0, 1)));
    const auto apart = analysis::vertex_fields(model, low, x, 1e-3, sim::residual_forces(model, low, x, 1e-3));
    for (std::size_t p = 0; p < x.size(); ++p) EXPECT_EQ(apart.contact[p], 0.0) << p;
    EXPECT_NEAR(apart.residual_force[0], model.mass(0) * model.gravity(), 1e-6 * weight);
}

TEST(VertexFields, ListNamesEveryFieldWithItsUnit)
{
    const auto model = cloth_model();
    const auto f = analysis::vertex_fields(model, geometry::ObstacleSet{}, affine_grid(Vec3(kSigma, 0, 0), Vec3(0, kSigma, 0)), 1e-3);
    const auto list = f.list();
    ASSERT_EQ(list.size(), 7u);
    const char* names[] = {"strain_warp", "strain_weft", "trellis_angle", "curvature_warp", "curvature_weft", "contact", "residual_force"};
    const char* units[] = {"1", "1", "rad", "1/m", "1/m", "1", "N"};
    for (int k = 0; k < 7; ++k) {
        EXPECT_EQ(list[k].name, names[k]);
        EXPECT_EQ(list[k].unit, units[k]);
        EXPECT_EQ(list[k].values.size(), static_cast<std::size_t>(kNu * kNv));
    }
}
