#pragma once
// Units: SI (m, kg, s, J, N) everywhere at the library surface. Kawabata (KES) values come in
// the instruments' units (gf.cm/cm, gf.cm2/cm, gf/cm, degrees, mg/cm2) and are converted here,
// in one place.
#include <numbers>

#include "woven/common/choice.hpp"

namespace woven::units {

/// The paper's gram-force: "1 gf is equivalent to 978.80 dynes" (Sec. 5.4 footnote), i.e. its
/// local g = 9.7880 m/s^2. Kept for reproduction of the paper's scaling.
inline constexpr double kPaperDynPerGramForce = 978.80;
/// Standard gram-force, 980.665 dyn (standard gravity).
inline constexpr double kStandardDynPerGramForce = 980.665;
/// Standard gravity (m/s^2), used for the gravity energy (Eq. 6) unless a scene says otherwise.
inline constexpr double kStandardGravity = 9.80665;

inline constexpr double kDynToNewton = 1e-5;
inline constexpr double kErgToJoule = 1e-7;
inline constexpr double kCmToM = 1e-2;
inline constexpr double kMToCm = 1e2;
inline constexpr double kDegToRad = std::numbers::pi / 180.0;
inline constexpr double kRadToDeg = 180.0 / std::numbers::pi;
/// Areal density: 1 mg/cm^2 = 0.01 kg/m^2 (= 10 g/m^2).
inline constexpr double kMgPerCm2ToKgPerM2 = 1e-2;

/// Which gram-force converts KES forces and moments.
enum class GramForce { PAPER, STANDARD };
/// The conventions' names: "paper", "standard" (scene files, reports).
inline constexpr std::array<Named<GramForce>, 2> kGramForceNames{{{GramForce::PAPER, "paper"}, {GramForce::STANDARD, "standard"}}};
/// Its name in kGramForceNames.
constexpr const char* to_string(GramForce gf) { return name_of(kGramForceNames, gf); }

/// Dynes per gram-force for the chosen convention.
constexpr double dyn_per_gram_force(GramForce gf)
{
    return gf == GramForce::PAPER ? kPaperDynPerGramForce : kStandardDynPerGramForce;
}
/// 1 gf.cm in J (gf.cm is the unit of the paper's bending and trellis energies before scaling).
constexpr double joule_per_gram_force_cm(GramForce gf) { return dyn_per_gram_force(gf) * kErgToJoule; }
/// 1 gf in N.
constexpr double newton_per_gram_force(GramForce gf) { return dyn_per_gram_force(gf) * kDynToNewton; }

}  // namespace woven::units
