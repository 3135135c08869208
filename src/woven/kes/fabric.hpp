#pragma once
// A fabric as measured on the Kawabata Evaluation System: areal density, first-stage bending
// curves (warp, weft; KES-FB2) and the first-stage shear curve (KES-FB1), in KES units.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "woven/kes/curve.hpp"

namespace woven::kes {

/// KES-FB2 summary values of one direction.
struct BendingSummary {
    double B = 0;         ///< bending rigidity, gf.cm^2/cm: slope between 0.5 and 1.5 1/cm
    double two_HB = 0;    ///< hysteresis width 2HB at 1.0 1/cm, gf.cm/cm
};

/// KES-FB1 summary values.
struct ShearSummary {
    double G = 0;         ///< shear rigidity, gf/(cm.deg): slope between 0.5 and 5 degrees
    double two_HG = 0;    ///< hysteresis width 2HG at 0.5 degrees, gf/cm
    double two_HG5 = 0;   ///< hysteresis width 2HG5 at 5 degrees, gf/cm
};

/// KES-FB1 tensile summary values (optional; not used by the drape model, kept for later use).
struct TensileSummary {
    double LT = 0;   ///< linearity, dimensionless
    double WT = 0;   ///< tensile energy, gf.cm/cm^2
    double RT = 0;   ///< resilience, %
    double EMT = 0;  ///< extension at 500 gf/cm, %
};

/// One measured property: the first-stage curve, and the summary values it was synthesised
/// from when the file gave summaries rather than points.
template <class Summary> struct Measured {
    Curve curve;
    std::optional<Summary> summary;  ///< set when the curve was synthesised from it
};

/// A fabric in KES units, as read from a fabric file.
struct FabricData {
    std::string name;
    std::string description;
    std::string source;          ///< where the numbers come from
    std::string representative;  ///< which numbers are representative rather than measured
    double areal_density_mg_cm2 = 0;  ///< W, mg/cm^2
    std::optional<double> thickness_mm;
    Measured<BendingSummary> bending_warp;  ///< KES-FB2, warp direction
    Measured<BendingSummary> bending_weft;  ///< KES-FB2, weft direction
    /// KES-FB2 (or a cantilever) on a bias specimen, cut at 45 degrees to the threads: its B,
    /// gf.cm^2/cm (beyond the paper: model::BiasBending). Unset: estimated from warp and weft.
    std::optional<double> bias_B;
    Measured<ShearSummary> shear;           ///< KES-FB1
    std::optional<TensileSummary> tensile;
    std::optional<std::array<double, 3>> color;  ///< display colour for pictures, sRGB in 0..1 (no physics)
};

/// KES instrument ranges and slope windows (KES-FB2 bending, KES-FB1 shear).
namespace instrument {
inline constexpr double kBendingMaxCurvature = 2.5;  ///< 1/cm
inline constexpr double kBendingSlopeFrom = 0.5, kBendingSlopeTo = 1.5;  ///< B window, 1/cm
inline constexpr double kShearMaxAngle = 8.0;  ///< degrees
inline constexpr double kShearSlopeFrom = 0.5, kShearSlopeTo = 5.0;  ///< G window, degrees
}  // namespace instrument

/// Where the synthesised curves' initial-resistance region ends (their hysteresis has risen to
/// its half width): 1/cm (bending), degrees (shear).
inline constexpr double kBendingRise = 0.3;
inline constexpr double kShearRise = 0.3;

/// Synthesises a first-stage KES-FB2 loading curve from B and 2HB (documented rule,
/// docs/FABRIC-FORMAT.md): M(K) = B K + (2HB/2) r(K/K1), r(u) = 1 - (1 - u)^2 for u < 1 and 1
/// beyond, K1 = 0.3 1/cm, K = 0..2.5 1/cm. The loading branch lies half a hysteresis width
/// above the mean line of slope B, reached (C1) by the end of the initial-resistance region,
/// so its KES slope over 0.5-1.5 1/cm is B exactly.
Curve synthesize_bending_curve(const BendingSummary& s);

/// Synthesises a first-stage KES-FB1 loading curve from G, 2HG, 2HG5 (documented rule):
/// F(phi) = G phi + h r(phi/phi1), r as above, phi1 = 0.3 deg, phi = 0..8 deg, with the half
/// hysteresis width h = (2HG + 2HG5)/4 (the mean of the two measured half widths): the
/// loading branch's KES slope over 0.5-5 degrees is G exactly.
Curve synthesize_shear_curve(const ShearSummary& s);

/// The fabric with the curves it gives by summary values replaced by their mean lines (2HB,
/// 2HG, 2HG5 set to 0 and the curves synthesised again: M = B K, F = G phi); curves given as
/// points are kept. The elastic part of the friction model (model::Hysteresis::FRICTION).
FabricData without_hysteresis(const FabricData& fabric);

/// Checks a fabric for plausibility and consistency; throws InputError naming `source` and the
/// field (e.g. "bending.warp.B") with what is expected. Returns warnings (values outside the
/// typical woven-fabric ranges, docs/FABRIC-FORMAT.md, but still physically possible).
std::vector<std::string> validate(const FabricData& f, const std::string& source);

/// Checks one curve (>= 3 points, finite, x strictly increasing from >= 0, y non-decreasing,
/// within `x_limit`). Throws InputError naming `source` and `field`.
void validate_curve(const Curve& c, const std::string& source, const std::string& field, double x_limit);

/// Fit options for bending and shear curves (line from 0.5 1/cm and 0.5 degrees).
FitOptions bending_fit_options();
FitOptions shear_fit_options();

}  // namespace woven::kes
