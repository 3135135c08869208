#include "woven/model/energy_functions.hpp"

#include <cmath>
#include <limits>
#include <numbers>

#include "woven/model/curvature.hpp"

namespace woven::model {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr Scalar3 kInfinite{kInf, 0, 0};
}  // namespace

Scalar3 ThreadSpacing::repulsion(double r) const
{
    if (r >= sigma) return {};
    if (r <= 0) return kInfinite;
    // R = C0 sigma u^5 / r with u = (sigma - r)/sigma.
    const double u = (sigma - r) / sigma;
    const double u2 = u * u, u3 = u2 * u, u4 = u3 * u, u5 = u4 * u;
    return {C0 * sigma * u5 / r,
            -C0 * sigma * u4 * (5.0 * r / sigma + u) / (r * r),
            C0 * sigma * (20.0 * u3 / (sigma * sigma * r) + 10.0 * u4 / (sigma * r * r) + 2.0 * u5 / (r * r * r))};
}

Scalar3 ThreadSpacing::stretch(double r) const
{
    if (tensile > 0) {
        // Within rounding of the rest length (a flat grid's neighbours are sigma apart only to
        // an ulp) no force: a cloth at rest is exactly at rest, as with the paper's well.
        const double d = std::abs(r - sigma) <= 1e-13 * sigma ? 0.0 : r - sigma;
        const double k = d < 0 ? compression_ratio * tensile : tensile;
        return {0.5 * k * d * d, k * d, k};
    }
    if (r <= sigma) return {};
    const double e = (r - sigma) / sigma;
    const double e3 = e * e * e;
    return {C0 * e3 * e * e, 5.0 * C0 * e3 * e / sigma, 20.0 * C0 * e3 / (sigma * sigma)};
}

double choose_C0(double areal_density_kg_m2, double gravity, double sigma, double hang_m, double max_strain)
{
    const double tension = areal_density_kg_m2 * gravity * hang_m * sigma;  // N per thread
    return tension * sigma / (5.0 * std::pow(max_strain, 4));
}

// ---------------------------------------------------------------------------------------------
BendingEnergy::BendingEnergy(kes::CurveFit moment, double sigma_m, BendingForm form, units::GramForce gf)
    : moment_(std::move(moment)), sigma_cm_(sigma_m * units::kMToCm), form_(form)
{
    scale_ = sigma_cm_ * sigma_cm_ * units::joule_per_gram_force_cm(gf);
}

Scalar3 BendingEnergy::of_curvature(double K) const
{
    const double M = moment_.value(K), dM = moment_.slope(K), d2M = moment_.curvature(K);
    if (form_ == BendingForm::SECANT)  // Eq. (12): B = M K sigma^2 / 2
        return {scale_ * M * K / 2.0, scale_ * (dM * K + M) / 2.0, scale_ * (d2M * K + 2.0 * dM) / 2.0};
    return {scale_ * moment_.integral(K), scale_ * M, scale_ * dM};
}

Scalar3 BendingEnergy::of_cosine(double c) const
{
    if (c >= 1.0) return kInfinite;
    const double s2 = sigma_cm_ * sigma_cm_;
    if (c < kBranchCosine) {
        // theta > pi/4, the circle branch: K^2 = 2 (1 + c) / sigma^2 is affine in c and
        // dK/dc = 1 / (sigma^2 K). The 1/K is cancelled analytically through M(K)/K.
        const double K = circle_curvature(c, sigma_cm_);
        const double Kd = std::max(K, 1e-9);  // d2 ~ 1/K: its product with |grad c|^2 ~ K^2 -> 0
        const double M = moment_.value(K), dM = moment_.slope(K), d2M = moment_.curvature(K);
        const double Ms = moment_.secant(K), dMs = moment_.secant_derivative(Kd);
        if (form_ == BendingForm::SECANT)
            return {scale_ * M * K / 2.0, scale_ * (dM + Ms) / (2.0 * s2), scale_ * (d2M + dMs) / (2.0 * s2 * s2 * Kd)};
        return {scale_ * moment_.integral(K), scale_ * Ms / s2, scale_ * dMs / (s2 * s2 * Kd)};
    }
    // theta <= pi/4: the a/theta + b branch of Eq. (13), through theta = acos(c).
    const double theta = std::acos(c);
    const double s = std::sqrt(1.0 - c * c);
    const double dtheta = -1.0 / s, d2theta = -c / (s * s * s);
    const CurvatureValue kv = thread_curvature(theta, sigma_cm_);
    const Scalar3 b = of_curvature(kv.K);
    const double dK = kv.dK * dtheta;
    return {b.value, b.d1 * dK, b.d2 * dK * dK + b.d1 * (kv.d2K * dtheta * dtheta + kv.dK * d2theta)};
}

double BendingEnergy::of_angle(double theta) const
{
    if (theta <= 0) return kInf;
    return of_curvature(thread_curvature(theta, sigma_cm_).K).value;
}

// ---------------------------------------------------------------------------------------------
TrellisEnergy::TrellisEnergy(kes::CurveFit force, double sigma_m, units::GramForce gf, double scale)
    : force_(std::move(force))
{
    const double sigma_cm = sigma_m * units::kMToCm;
    scale_ = scale * sigma_cm * sigma_cm * units::joule_per_gram_force_cm(gf);
    phi_e_ = force_.data_max_x() * units::kDegToRad;
    // Singular continuation a/(1.05 - phi) + b matching T and dT/dphi at phi_e (Sec. 5.3).
    const double Te = scale_ * integral(phi_e_);
    const double dTe = scale_ * force_.value(phi_e_ * units::kRadToDeg) * std::cos(phi_e_);
    const double gap = kSingularAngle - phi_e_;
    a_ = dTe * gap * gap;
    b_ = Te - a_ / gap;
}

double TrellisEnergy::integral(double phi) const
{
    // F is fitted in degrees: F = c0 + c1 x + c2 x^2, x = k psi. In radians the coefficients are
    // (c0, c1 k, c2 k^2). Each piece of integral_lo^hi (A + B psi + C psi^2) cos psi is summed by
    // 8-point Gauss-Legendre, exact to rounding for these entire integrands on pieces up to the
    // KES range (error bound ~1e-23 (hi - lo)^17 max|f^(16)|). Not the closed form through
    // sin/cos primitives: its differences cancel (cos t - 1, t^2 sin t + 2 t cos t - 2 sin t),
    // which lost all relative precision for phi below ~1e-7 rad (T(1e-8) came out 0) and made
    // the trellis gradient fail finite-difference checks (tests/model/test_derivatives.cpp).
    static constexpr double kNode[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
    static constexpr double kWeight[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};
    const double k = units::kRadToDeg;
    double total = 0;
    for (const kes::Segment& s : force_.segments()) {
        const double lo = s.x_begin / k;
        const double hi = std::min(s.x_end / k, phi);
        if (hi > lo) {
            const double A = s.c0, B = s.c1 * k, C = s.c2 * k * k;
            auto f = [&](double t) { return (A + t * (B + t * C)) * std::cos(t); };
            const double mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
            double sum = 0;
            for (int q = 0; q < 4; ++q) sum += kWeight[q] * (f(mid - half * kNode[q]) + f(mid + half * kNode[q]));
            total += half * sum;
        }
        if (phi <= s.x_end / k) break;
    }
    return total;
}

Scalar3 TrellisEnergy::of_angle(double phi) const
{
    const double p = std::abs(phi);
    const double sign = phi < 0 ? -1.0 : 1.0;
    if (p >= kSingularAngle) return kInfinite;
    if (p <= phi_e_) {
        const double F = force_.value(p * units::kRadToDeg);
        const double dF = force_.slope(p * units::kRadToDeg) * units::kRadToDeg;
        return {scale_ * integral(p), sign * scale_ * F * std::cos(p), scale_ * (dF * std::cos(p) - F * std::sin(p))};
    }
    const double gap = kSingularAngle - p;
    return {a_ / gap + b_, sign * a_ / (gap * gap), 2.0 * a_ / (gap * gap * gap)};
}

Scalar3 TrellisEnergy::of_cosine(double c) const
{
    const double ac = std::abs(c);
    if (ac >= 1.0) return kInfinite;
    const double p = std::asin(ac);  // |phi|
    if (p >= kSingularAngle) return kInfinite;
    const Scalar3 t = of_angle(p);
    const double cp = std::sqrt(1.0 - c * c);  // cos(phi)
    const double sign = c > 0 ? 1.0 : (c < 0 ? -1.0 : 0.0);
    return {t.value, sign * t.d1 / cp, t.d2 / (cp * cp) + t.d1 * ac / (cp * cp * cp)};
}

}  // namespace woven::model
