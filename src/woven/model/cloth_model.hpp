#pragma once
// The global energy of the cloth (MODEL-NOTES "write it once, globally"), each term once:
//
//   E = sum_{pairs i<j, r_ij < sigma} R(r_ij)            (Eq. 2, 4; all pairs, spatial hash)
//     + sum_{4-connected edges}        S(r_ij)            (Eq. 3, 5)
//     + sum_{particles k} B_warp(theta_k,warp) + B_weft(theta_k,weft)   (Eq. 7, 12)
//     + sum_{interior particles k}     T(phi_k)           (Eq. 8, 15)
//     + sum_k m g z_k                                     (Eq. 6)
//
// Grid and thread convention (MODEL-NOTES), stated once here: particle (i, j) has index
// i + nu * j; weft threads run along i (u direction), warp threads along j (v direction). The
// warp bending angle at (i, j) is formed by (i, j-1), (i, j), (i, j+1) and uses the KES warp
// curve; the weft angle by (i-1, j), (i, j), (i+1, j) with the weft curve. The trellis angle at
// an interior particle k is the angle between (i-1,j)->(i+1,j) and (i,j-1)->(i,j+1) minus 90
// degrees. Height is z; gravity acts along -z.
#include <vector>

#include "woven/common/types.hpp"
#include "woven/kes/fabric.hpp"
#include "woven/model/energy_functions.hpp"

namespace woven::model {

/// The particle grid: nu x nv particles at rest spacing sigma (m).
struct Grid {
    int nu = 0, nv = 0;
    double sigma = 0;
    int index(int i, int j) const { return i + nu * j; }
    int size() const { return nu * nv; }
};

/// The terms of Eq. (1), each summed once over the cloth (J).
struct EnergyTerms {
    double repulsion = 0, stretch = 0, bending_warp = 0, bending_weft = 0, trellis = 0, gravity = 0;
    double total() const { return repulsion + stretch + bending_warp + bending_weft + trellis + gravity; }
};

/// What the model computes besides the energy.
enum class Derivatives {
    NONE,       ///< energy only
    GRADIENT,   ///< energy and gradient
    HESSIAN,    ///< + exact Hessian per term
    PROJECTED,  ///< + per-term positive semi-definite Hessian (Gauss-Newton, see cloth_model.cpp)
};

/// Receives each term's local contribution: n particles, the value, the gradient (3n) and, when
/// asked, the Hessian (3n x 3n, column-major). Solvers scatter these into their own storage.
class StencilSink {
public:
    virtual ~StencilSink() = default;
    virtual void add(const int* particles, int n, const double* gradient, const double* hessian) = 0;
};

/// Model settings beyond the fabric (SI).
struct ModelOptions {
    BendingForm bending_form = BendingForm::SECANT;
    units::GramForce gram_force = units::GramForce::PAPER;
    double gravity = units::kStandardGravity;  ///< m/s^2
    /// C0 of Eq. (2, 3) in J; <= 0: chosen by choose_C0 for a hanging length of half the
    /// cloth's longer side and 1 % strain.
    double C0 = 0;
};

/// The cloth's energy of Eq. (1) with derivatives, for one fabric and grid.
class ClothModel {
public:
    ClothModel(Grid grid, double particle_mass, double gravity, ThreadSpacing spacing, BendingEnergy warp, BendingEnergy weft, TrellisEnergy trellis);

    /// Energy terms at x; a term is +inf in a singular configuration (trellis past 1.05 rad, a
    /// thread folded to theta = 0, two particles at the same place). With derivatives, each
    /// stencil's local gradient (and Hessian) is sent to `sink` (not called for zero terms).
    EnergyTerms evaluate(const Positions& x, Derivatives what = Derivatives::NONE, StencilSink* sink = nullptr) const;

    /// Total energy (J).
    double energy(const Positions& x) const { return evaluate(x).total(); }
    /// Gradient dE/dx (N... J/m), 3n vector.
    Eigen::VectorXd gradient(const Positions& x) const;

    /// Pairs i < j closer than `radius` (default: sigma, the repulsion's support), by a spatial
    /// hash: O(n).
    std::vector<std::pair<int, int>> close_pairs(const Positions& x, double radius = 0) const;

    const Grid& grid() const { return grid_; }
    double particle_mass() const { return mass_; }
    double gravity() const { return gravity_; }
    const ThreadSpacing& spacing() const { return spacing_; }
    const BendingEnergy& bending_warp() const { return warp_; }
    const BendingEnergy& bending_weft() const { return weft_; }
    const TrellisEnergy& trellis() const { return trellis_; }

private:
    Grid grid_;
    double mass_, gravity_;
    ThreadSpacing spacing_;
    BendingEnergy warp_, weft_;
    TrellisEnergy trellis_;
};

/// Builds the model for a fabric: fits its curves (Sec. 5.1), derives B and T (Sec. 5.2-5.4),
/// particle mass m = W sigma^2 (MODEL-NOTES) and C0.
ClothModel make_cloth_model(const kes::FabricData& fabric, Grid grid, const ModelOptions& options);

/// The flat grid at height z, centred at (cx, cy), rotated by `yaw` (rad) about the vertical.
Positions flat_grid(const Grid& grid, const Vec3& centre, double yaw = 0.0);

}  // namespace woven::model
