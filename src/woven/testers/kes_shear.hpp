#pragma once
// Virtual KES-FB1 shear test: a specimen 20 cm long (the clamps' length) and 5 cm between the
// clamps, gravity off, one long edge held, the other moved sideways to shear angle
// phi = 0 .. 8 degrees in steps under the standard 10 gf/cm pre-tension, at static equilibrium
// at each step. The force per unit length is the derivative of the equilibrium energy with
// respect to the clamp's motion; G is its KES slope between 0.5 and 5 degrees.
//
// How the specimen maps onto the grid: the clamps are two grid rows, each one row of particles
// (a shear clamp holds the edge's position only), N = round(5 cm / sigma) spacings apart, with
// round(20 cm / sigma) + 1 particles along them; the direction named is that of the threads
// running along the clamps (the other family crosses between them). The pre-tension is
// applied at phi = 0 as the clamp separation l' = N sigma (1 + eps) at which the crossing
// threads carry 10 gf/cm (found by static solves); then the moving clamp turns about the
// fixed one at that separation, to (l' sin phi, l' cos phi), as the inextensible crossing
// threads of a taut specimen do. The reported force is the shear force of Eq. (14),
//   F = dE/dphi / (A cos phi),  A = the specimen's rest area (20 x 5 cm^2),
// the lateral reaction less the pre-tension's own lateral share (F_N tan phi), which the
// paper's trellis energy (Eq. 14-15) does not contain.
//
// The specimen's short edges are free, as on the instrument: a free edge carries no shear
// stress, so the shear relaxes over a few centimetres from each end and the whole clamp reads
// a G below the material's, by an amount that falls as 1 / length (linen, G 2.0 gf/(cm.deg) at
// 10 gf/cm, sigma 0.25 cm: -1.09 / -0.55 / -0.27 % with a 20 / 40 / 80 cm clamp; at 20 cm
// -0.46 / -0.80 / -1.09 % at sigma 1 / 0.5 / 0.25 cm, growing as the grid resolves the edge
// layer: a continuum end effect, which the real instrument has too). The curve of the middle
// half of the moving clamp (KesCurveResult::y_central) leaves the ends out: on an 80 cm clamp
// it is the material's law to 0.02 %; on the standard 20 cm one it still carries half the end
// effect (those numbers with the shear law as measured). shear_deembedding finds the
// material's law whose 20 cm reading is the input (model::ShearLaw::DEEMBEDDED).
#include "woven/testers/kes_bending.hpp"

namespace woven::testers {

/// Settings of the FB1 test (SI unless stated).
struct ShearTestOptions {
    double sigma = 0.0025;      ///< nominal spacing, m
    double length = 0.20;       ///< along the clamps, m
    double gap = 0.05;          ///< between the clamps, m
    double max_angle = 8.0;     ///< degrees
    double step = 0.5;          ///< degrees
    double pretension = 10.0;   ///< gf/cm
    /// The angles to load to (degrees, increasing, covering the G window); empty: 0 .. max_angle
    /// in `step`s. Each angle is solved from the uniformly sheared placement, so a list gives
    /// the same points as the full sweep.
    std::vector<double> angles;
    model::ModelOptions model;  ///< gravity is switched off
    StaticOptions solve;
};

/// Runs the FB1 test with the clamps along the threads of direction `d`.
KesCurveResult kes_shear_test(const kes::FabricData& fabric, Direction d, const ShearTestOptions& options);

/// The spacing the shear law is de-embedded at (m): fine enough to resolve most of the end
/// effect (linen reads -0.80 % at 0.5 cm, -1.09 % at 0.25 cm, -0.46 % at 1 cm), coarse enough
/// to cost a fraction of a second.
inline constexpr double kDeembeddingSpacing = 0.005;

/// The factor by which the material's shear law exceeds the KES-FB1 reading it was measured
/// as: the 20 x 5 cm specimen's free short edges carry no shear, so the instrument reads a G
/// below the material's (kes_shear.hpp). Runs the virtual FB1 (warp along the clamps: the
/// trellis energy knows no direction) at the G window's ends at `sigma` and iterates
/// s <- s G_input / G_read(s) until the reading matches the input to `tolerance` (relative).
/// `model.shear_scale` is ignored. Returns 1 for the paper's discretization (kept literal) and
/// for a curve that ends before the window (nothing to read).
double shear_deembedding(const kes::FabricData& fabric, const model::ModelOptions& model, double sigma = kDeembeddingSpacing,
                         double tolerance = 1e-3);

}  // namespace woven::testers
