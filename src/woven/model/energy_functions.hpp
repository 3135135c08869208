#pragma once
// The scalar energy functions of the model, each with its first two derivatives:
//   R(r), S(r)  repulsion and stretching (Eq. 2, 3), shared scale C0
//   B           bending energy of one thread angle (Eq. 9-13) from a fitted KES-FB2 curve
//   T           trellis energy of one crossing (Eq. 14-15) from a fitted KES-FB1 curve
// Energies are in J; lengths in m at the interface (KES units inside, converted once).
#include "woven/common/units.hpp"
#include "woven/kes/curve.hpp"

namespace woven::model {

/// A scalar function's value and first two derivatives.
struct Scalar3 {
    double value = 0;
    double d1 = 0;
    double d2 = 0;
};

/// Repulsion and stretching (Eq. 2, 3), the non-empirical energy well that keeps 4-connected
/// particles at sigma and all particles apart:
///   R(r) = C0 ((sigma - r)/sigma)^5 (sigma / r)   for r <= sigma, else 0
///   S(r) = C0 ((r - sigma)/sigma)^5               for r >  sigma, else 0
/// Departure from the paper: Eq. (2) reads C0 (sigma - r)^5 / r, whose C0 would carry J/m^4
/// while Eq. (3)'s carries J; dividing lengths by sigma gives both the same C0 in J with the
/// same shape.
struct ThreadSpacing {
    double C0 = 0;     ///< J
    double sigma = 0;  ///< m
    /// > 0 (the convergent discretisation): the thread is a linear spring instead, the stretch
    /// S(r) = E_t (r - sigma)^2 / 2 in tension and compression (a segment of width and length
    /// sigma stores E_t eps^2 / 2 per unit area, eps = (r - sigma)/sigma), E_t in N/m; the
    /// repulsion R keeps C0.
    double tensile = 0;
    /// The convergent thread's stiffness in compression over its tensile one, in [0, 1]: 1 (the
    /// default) a linear spring both ways; 0 the paper's Eq. (3), no resistance below sigma (a
    /// yarn buckles), where only the repulsion R holds the particles apart.
    double compression_ratio = 1;

    Scalar3 repulsion(double r) const;
    Scalar3 stretch(double r) const;
};

/// Chooses C0 so that a thread carrying the weight of a hanging length `hang_m` of cloth
/// (tension W g hang sigma per thread) is stretched by at most `max_strain` (docs/MODEL.md "Eq. 2's units": about
/// 1 %): S'(r) = 5 C0 eps^4 / sigma = tension.
double choose_C0(double areal_density_kg_m2, double gravity, double sigma, double hang_m, double max_strain = 0.01);

/// Form of the bending energy of Eq. (12).
enum class BendingForm {
    SECANT,  ///< the paper's B = M(K) K sigma^2 / 2 (default)
    WORK,    ///< the work integral B = sigma^2 * integral_0^K M dK (equal to SECANT for linear M)
};

/// Bending energy of one thread angle theta (Eq. 12 with K from the corrected Eq. 13), in J:
///   B = (M(K) K / 2) sigma^2 [gf.cm] * (dyn per gf) * 1e-7,   M in gf.cm/cm, K in 1/cm, sigma in cm.
/// It is evaluated as a function of c = cos(theta), which is smooth in the positions even for
/// a straight thread (theta = pi), where theta itself is not differentiable.
class BendingEnergy {
public:
    BendingEnergy() = default;
    BendingEnergy(kes::CurveFit moment, double sigma_m, BendingForm form, units::GramForce gf);

    /// B and dB/dc, d2B/dc2 at c = cos(theta); value +inf at c >= 1 (theta = 0).
    Scalar3 of_cosine(double c) const;
    /// B(theta), J.
    double of_angle(double theta) const;
    /// B as a function of curvature K (1/cm): value, dB/dK, d2B/dK2.
    Scalar3 of_curvature(double K) const;

    const kes::CurveFit& moment() const { return moment_; }
    double sigma_cm() const { return sigma_cm_; }

private:
    kes::CurveFit moment_;
    double sigma_cm_ = 0;
    double scale_ = 0;  ///< sigma_cm^2 * (J per gf.cm)
    BendingForm form_ = BendingForm::SECANT;
};

/// Trellis energy of one crossing with trellis angle phi (Eq. 15 with the paper's scaling):
///   T(phi) = (dyn per gf) * sigma_cm^2 * integral_0^|phi| F(psi) cos(psi) dpsi  [erg] * 1e-7  [J]
/// (the paper's 195.76 sigma^2 times l = 5 cm), F in gf/cm, psi in radians. Past the last
/// measured angle phi_e: T = a / (1.05 - |phi|) + b, a and b matching T and dT/dphi at phi_e
/// (Sec. 5.3); +inf at |phi| >= 1.05.
class TrellisEnergy {
public:
    /// The paper's stand-in for 60 degrees (Sec. 5.3).
    static constexpr double kSingularAngle = 1.05;

    TrellisEnergy() = default;
    /// `scale` multiplies the force curve (ModelOptions::shear_scale).
    TrellisEnergy(kes::CurveFit force, double sigma_m, units::GramForce gf, double scale = 1.0);

    /// T(phi), dT/dphi, d2T/dphi2 (phi in radians, J). T is even.
    Scalar3 of_angle(double phi) const;
    /// T as a function of c = cos(angle between the two thread segments) = -sin(phi).
    Scalar3 of_cosine(double c) const;
    /// phi_e, the last measured angle (rad).
    double last_measured_angle() const { return phi_e_; }
    /// a and b of the singular continuation.
    double continuation_a() const { return a_; }
    double continuation_b() const { return b_; }
    const kes::CurveFit& force() const { return force_; }

private:
    double integral(double phi) const;  ///< integral_0^phi F cos, phi in [0, phi_e]
    kes::CurveFit force_;
    double scale_ = 0;  ///< sigma_cm^2 * (J per gf.cm)
    double phi_e_ = 0;
    double a_ = 0, b_ = 0;
};

}  // namespace woven::model
