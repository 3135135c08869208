// The scalar energy functions: repulsion/stretch (Eq. 2-3) and choose_C0, bending B(c) (Eq. 9-13)
// in SECANT and WORK form, trellis T(phi) (Eq. 14-15 and the singular continuation). Values by
// hand with units, derivatives against finite differences, continuity at every seam.
#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "model/model_test_support.hpp"
#include "woven/model/curvature.hpp"
#include "woven/model/energy_functions.hpp"

namespace woven::test {
namespace {

using model::BendingEnergy;
using model::BendingForm;
using model::Scalar3;
using model::ThreadSpacing;
using model::TrellisEnergy;

constexpr double kPi = std::numbers::pi;
constexpr double kPaperJoulePerGfCm = 978.80e-7;  // the paper's 1 gf = 978.80 dyn; 1 erg = 1e-7 J
constexpr double kSigma = 0.02;                    // m (2 cm, the paper's 51 x 51 metre cloth)

// ---------------------------------------------------------------------------------------------
// Repulsion and stretch.

TEST(HandValues, StretchAtOnePercent)
{
    // S(1.01 sigma) = C0 ((r - sigma)/sigma)^5 = 1000 J * 0.01^5 = 1000 J * 1e-10 = 1e-7 J.
    const ThreadSpacing t{1000.0, kSigma};
    EXPECT_NEAR(t.stretch(1.01 * kSigma).value, 1e-7, 1e-7 * 1e-9);
    // S' = 5 C0 e^4 / sigma = 5 * 1000 * 1e-8 / 0.02 m = 2.5e-3 N.
    EXPECT_NEAR(t.stretch(1.01 * kSigma).d1, 2.5e-3, 2.5e-3 * 1e-9);
    EXPECT_EQ(t.repulsion(1.01 * kSigma).value, 0.0);
}

TEST(HandValues, ConvergentThreadInCompression)
{
    // E_t = 500 N/m, sigma = 2 cm, compression ratio 0.1: at 1 % shortening d = -2e-4 m the
    // stiffness is 50 N/m: S = 50 * 4e-8 / 2 = 1e-6 J, S' = 50 * -2e-4 = -0.01 N; at 1 % extension
    // the tensile 500 N/m: S = 1e-5 J, S' = 0.1 N.
    const ThreadSpacing soft{1000.0, kSigma, 500.0, 0.1};
    EXPECT_NEAR(soft.stretch(0.99 * kSigma).value, 1e-6, 1e-6 * 1e-9);
    EXPECT_NEAR(soft.stretch(0.99 * kSigma).d1, -0.01, 0.01 * 1e-9);
    EXPECT_NEAR(soft.stretch(0.99 * kSigma).d2, 50.0, 50.0 * 1e-12);
    EXPECT_NEAR(soft.stretch(1.01 * kSigma).value, 1e-5, 1e-5 * 1e-9);
    EXPECT_NEAR(soft.stretch(1.01 * kSigma).d1, 0.1, 0.1 * 1e-9);
    // Ratio 0: the paper's Eq. (3), nothing below sigma; the default 1: the same spring both ways.
    const ThreadSpacing buckling{1000.0, kSigma, 500.0, 0.0};
    EXPECT_EQ(buckling.stretch(0.99 * kSigma).value, 0.0);
    EXPECT_EQ(buckling.stretch(0.99 * kSigma).d1, 0.0);
    const ThreadSpacing linear{1000.0, kSigma, 500.0};
    EXPECT_NEAR(linear.stretch(0.99 * kSigma).value, 1e-5, 1e-5 * 1e-9);
}

TEST(HandValues, RepulsionAtHalfSigma)
{
    // R(sigma/2) = C0 ((sigma - r)/sigma)^5 (sigma/r) = 1000 J * (1/2)^5 * 2 = 62.5 J.
    const ThreadSpacing t{1000.0, kSigma};
    EXPECT_NEAR(t.repulsion(0.5 * kSigma).value, 62.5, 62.5 * 1e-12);
    // R' = -C0 sigma u^4 (5 r/sigma + u) / r^2 = -1000 * 0.02 * (1/16) * 3 / 1e-4 = -37500 N.
    EXPECT_NEAR(t.repulsion(0.5 * kSigma).d1, -37500.0, 37500.0 * 1e-12);
    EXPECT_EQ(t.stretch(0.5 * kSigma).value, 0.0);
    EXPECT_TRUE(std::isinf(t.repulsion(0.0).value));
}

TEST(HandValues, ChooseC0ForCotton)
{
    // Cotton-like: W = 15 mg/cm^2 = 0.15 kg/m^2, g = 9.80665 m/s^2, sigma = 2 cm, hanging length
    // 0.5 m: tension per thread = W g hang sigma = 0.15 * 9.80665 * 0.5 * 0.02 = 0.014709975 N;
    // S'(1.01 sigma) = 5 C0 (0.01)^4 / sigma = tension  =>  C0 = 0.014709975 * 0.02 / 5e-8 = 5883.99 J.
    const double C0 = model::choose_C0(0.15, 9.80665, 0.02, 0.5);
    EXPECT_NEAR(C0, 5883.99, 5883.99 * 1e-12);
    const ThreadSpacing t{C0, 0.02};
    EXPECT_NEAR(t.stretch(1.01 * 0.02).d1, 0.014709975, 0.014709975 * 1e-12);
    // Another strain: the force at that strain is the tension.
    const ThreadSpacing t2{model::choose_C0(0.15, 9.80665, 0.02, 0.5, 0.02), 0.02};
    EXPECT_NEAR(t2.stretch(1.02 * 0.02).d1, 0.014709975, 1e-14);
}

class SpacingDerivatives : public testing::TestWithParam<double> {};  // r / sigma

TEST_P(SpacingDerivatives, MatchFiniteDifferences)
{
    const ThreadSpacing t{cotton_C0(kSigma), kSigma};
    const double r = GetParam() * kSigma, h = 1e-7 * r;
    auto check = [&](auto f, const char* what) {
        const Scalar3 v = f(r), p = f(r + h), m = f(r - h);
        EXPECT_NEAR((p.value - m.value) / (2 * h), v.d1, 1e-6 * std::abs(v.d1)) << what;
        EXPECT_NEAR((p.d1 - m.d1) / (2 * h), v.d2, 1e-6 * std::abs(v.d2)) << what;
    };
    if (GetParam() < 1) {
        check([&](double x) { return t.repulsion(x); }, "repulsion");
        EXPECT_GT(t.repulsion(r).value, 0.0);
        EXPECT_LT(t.repulsion(r).d1, 0.0);
    } else {
        check([&](double x) { return t.stretch(x); }, "stretch");
        EXPECT_GT(t.stretch(r).value, 0.0);
        EXPECT_GT(t.stretch(r).d1, 0.0);
    }
}
INSTANTIATE_TEST_SUITE_P(Radii, SpacingDerivatives, testing::Values(0.02, 0.1, 0.5, 0.9, 0.99, 0.999, 1.001, 1.01, 1.1, 1.5));

TEST(Spacing, SmoothAtSigma)
{
    // Both vanish at sigma with their first four derivatives: values and d1, d2 go to 0.
    const ThreadSpacing t{cotton_C0(kSigma), kSigma};
    for (double e : {1e-3, 1e-4}) {
        EXPECT_LT(t.repulsion((1 - e) * kSigma).d2, 1e3 * t.C0 * std::pow(e, 3) / (kSigma * kSigma));
        EXPECT_LT(t.stretch((1 + e) * kSigma).d2, 1e3 * t.C0 * std::pow(e, 3) / (kSigma * kSigma));
    }
    EXPECT_EQ(t.repulsion(kSigma).value, 0.0);
    EXPECT_EQ(t.stretch(kSigma).value, 0.0);
}

// ---------------------------------------------------------------------------------------------
// Bending.

BendingEnergy linear_bending(double B, BendingForm form) { return BendingEnergy(smooth_curve(B, 0.0, 2.5), kSigma, form, units::GramForce::PAPER); }

TEST(HandValues, BendingLinearMomentCircleBranch)
{
    // M = B K, B = 0.1 gf.cm^2/cm, sigma = 2 cm, theta = pi/2: K = (2/sigma) cos(pi/4) = 0.70710678 1/cm.
    // B_energy = B K^2 / 2 * sigma_cm^2 * 978.80e-7 J = 0.1 * 0.5 / 2 * 4 * 978.80e-7 = 9.788e-6 J.
    for (BendingForm form : {BendingForm::SECANT, BendingForm::WORK}) {
        const BendingEnergy b = linear_bending(0.1, form);
        EXPECT_NEAR(b.of_angle(kPi / 2), 9.788e-6, 9.788e-6 * 1e-12);
        EXPECT_NEAR(b.of_cosine(0.0).value, 9.788e-6, 9.788e-6 * 1e-12);
    }
}

TEST(HandValues, BendingLinearMomentSmallAngleBranch)
{
    // theta = pi/8 (below pi/4): corrected Eq. (13), sigma = 2 cm: alpha = cos(pi/8) = 0.92387953,
    // beta = sin(pi/8)/2 = 0.19134172, K = (pi/4)^2 beta/(pi/8) + alpha - (pi/4) beta
    // = alpha + (pi/4) beta = 1.07415896 1/cm. B_energy = 0.1 * 1.07415896^2 / 2 * 4 * 978.80e-7
    // = 2.2587131e-5 J.
    const BendingEnergy b = linear_bending(0.1, BendingForm::SECANT);
    EXPECT_NEAR(model::thread_curvature(kPi / 8, 2.0).K, 1.0741589649823733, 1e-12);
    EXPECT_NEAR(b.of_angle(kPi / 8), 2.2587131028650023e-05, 2.2587131e-5 * 1e-9);
    EXPECT_NEAR(b.of_cosine(std::cos(kPi / 8)).value, 2.2587131028650023e-05, 2.2587131e-5 * 1e-9);
}

TEST(HandValues, StandardGramForce)
{
    // The STANDARD option converts with 980.665 dyn/gf instead of the paper's 978.80.
    const BendingEnergy p(smooth_curve(0.1, 0, 2.5), kSigma, BendingForm::SECANT, units::GramForce::PAPER);
    const BendingEnergy s(smooth_curve(0.1, 0, 2.5), kSigma, BendingForm::SECANT, units::GramForce::STANDARD);
    EXPECT_NEAR(s.of_angle(1.0) / p.of_angle(1.0), 980.665 / 978.80, 1e-14);
}

TEST(Bending, SecantAndWorkAgreeForLinearMoment)
{
    const BendingEnergy s = linear_bending(0.07, BendingForm::SECANT), w = linear_bending(0.07, BendingForm::WORK);
    for (double theta : {0.05, 0.3, kPi / 4 - 1e-3, kPi / 4 + 1e-3, 1.2, 2.5, kPi - 1e-3, kPi}) {
        const Scalar3 a = s.of_cosine(std::cos(theta)), b = w.of_cosine(std::cos(theta));
        EXPECT_NEAR(a.value, b.value, 1e-12 * std::abs(a.value) + 1e-30) << theta;
        EXPECT_NEAR(a.d1, b.d1, 1e-12 * std::abs(a.d1)) << theta;
        if (theta < kPi) {
            EXPECT_NEAR(a.d2, b.d2, 1e-10 * std::abs(a.d2)) << theta;
        }
    }
    // ...and differ for a nonlinear one: SECANT c1 K^2/2 + c2 K^3/2, WORK c1 K^2/2 + c2 K^3/3.
    const BendingEnergy sq(smooth_curve(0.07, 0.05, 2.5), kSigma, BendingForm::SECANT, units::GramForce::PAPER);
    const BendingEnergy wq(smooth_curve(0.07, 0.05, 2.5), kSigma, BendingForm::WORK, units::GramForce::PAPER);
    const double K = 0.8, scale = 4.0 * kPaperJoulePerGfCm;
    EXPECT_NEAR(sq.of_curvature(K).value, scale * (0.07 * K * K / 2 + 0.05 * K * K * K / 2), 1e-18);
    EXPECT_NEAR(wq.of_curvature(K).value, scale * (0.07 * K * K / 2 + 0.05 * K * K * K / 3), 1e-18);
}

TEST(Bending, ZeroAndFiniteSlopeWhenStraight)
{
    for (BendingForm form : {BendingForm::SECANT, BendingForm::WORK}) {
        for (const kes::CurveFit& M : {fitted_bending(cotton_warp()), smooth_curve(0.06, 0.02, 2.5)}) {
            const BendingEnergy b(M, kSigma, form, units::GramForce::PAPER);
            EXPECT_EQ(b.of_cosine(-1.0).value, 0.0);
            EXPECT_NEAR(b.of_angle(kPi), 0.0, 1e-30);
            // dB/dc at c = -1: K^2 = 2 (1 + c)/sigma^2, so dB/dc = M'(0) sigma_cm^2 J/(gf.cm) / sigma_cm^2
            // = M'(0) * 978.80e-7 J for both forms (SECANT: (M' + M/K)/2 -> M'(0)).
            const Scalar3 v = b.of_cosine(-1.0);
            EXPECT_TRUE(std::isfinite(v.d1));
            EXPECT_NEAR(v.d1, M.slope(0.0) * kPaperJoulePerGfCm, 1e-12 * M.slope(0.0) * kPaperJoulePerGfCm);
            EXPECT_GT(v.d1, 0.0);
            // the slope is continuous at c = -1
            EXPECT_NEAR(b.of_cosine(-1.0 + 1e-12).d1, v.d1, 1e-5 * v.d1);
        }
    }
    EXPECT_TRUE(std::isinf(linear_bending(0.1, BendingForm::SECANT).of_cosine(1.0).value));
    EXPECT_TRUE(std::isinf(linear_bending(0.1, BendingForm::SECANT).of_angle(0.0)));
}

struct BendingCase {
    double theta;
    bool fitted;
    BendingForm form;
};
class BendingDerivatives : public testing::TestWithParam<BendingCase> {};

TEST_P(BendingDerivatives, OfCosineMatchesFiniteDifferences)
{
    const auto [theta, fitted, form] = GetParam();
    const kes::CurveFit M = fitted ? fitted_bending(cotton_weft()) : smooth_curve(0.15, 0.03, 2.5);
    const BendingEnergy b(M, kSigma, form, units::GramForce::PAPER);
    const double c = std::cos(theta);
    // Step: small against the distance to the seams in c (c = -1, c = cos(pi/4), c = 1).
    const double room = std::min({1.0 + c, std::abs(c - std::numbers::sqrt2 / 2), 1.0 - c});
    const double h = 1e-4 * room;
    // The fitted moment has C1 junctions: keep K off them by more than the step.
    const double K = model::thread_curvature(theta, b.sigma_cm()).K;
    const double dK = std::abs(model::thread_curvature(theta, b.sigma_cm()).dK) / std::sin(theta) * h * 10;
    for (const kes::Segment& s : M.segments())
        if (std::abs(K - s.x_end) < dK) GTEST_SKIP() << "K on a junction of the fit";
    auto at = [&](double cc) { return b.of_cosine(cc); };
    const Scalar3 v = at(c);
    const double fd1 = (8 * (at(c + h).value - at(c - h).value) - (at(c + 2 * h).value - at(c - 2 * h).value)) / (12 * h);
    const double fd2 = (8 * (at(c + h).d1 - at(c - h).d1) - (at(c + 2 * h).d1 - at(c - 2 * h).d1)) / (12 * h);
    EXPECT_NEAR(fd1, v.d1, 1e-6 * std::abs(v.d1));
    EXPECT_NEAR(fd2, v.d2, 1e-6 * std::abs(v.d2));
    EXPECT_NEAR(b.of_angle(theta), v.value, 1e-12 * v.value);
    // In curvature too.
    const Scalar3 k = b.of_curvature(K);
    const double hk = 1e-5 * K;
    EXPECT_NEAR((b.of_curvature(K + hk).value - b.of_curvature(K - hk).value) / (2 * hk), k.d1, 1e-6 * std::abs(k.d1));
}

std::vector<BendingCase> bending_cases()
{
    std::vector<BendingCase> v;
    for (double theta : {0.02, 0.1, 0.3, 0.6, kPi / 4 - 1e-3, kPi / 4 + 1e-3, 1.0, 1.6, 2.2, 2.8, 3.0, kPi - 0.05, kPi - 0.01})
        for (bool fitted : {false, true})
            for (BendingForm form : {BendingForm::SECANT, BendingForm::WORK}) v.push_back({theta, fitted, form});
    return v;
}
INSTANTIATE_TEST_SUITE_P(Sweep, BendingDerivatives, testing::ValuesIn(bending_cases()));

TEST(Bending, ContinuousAtQuarterPi)
{
    // K is C1 at pi/4, so B(c) is C0 and C1 there (relative 1e-9).
    for (BendingForm form : {BendingForm::SECANT, BendingForm::WORK})
        for (const kes::CurveFit& M : {fitted_bending(cotton_warp()), smooth_curve(0.06, 0.02, 2.5)}) {
            const BendingEnergy b(M, kSigma, form, units::GramForce::PAPER);
            const double c = std::numbers::sqrt2 / 2;
            const Scalar3 lo = b.of_cosine(std::nextafter(c, 0.0)), hi = b.of_cosine(c);  // theta above / at-or-below pi/4
            EXPECT_NEAR(lo.value, hi.value, 1e-9 * hi.value);
            EXPECT_NEAR(lo.d1, hi.d1, 1e-9 * std::abs(hi.d1));
            EXPECT_GT(hi.d1, 0.0);  // more bending (larger c) costs more energy
        }
}

// ---------------------------------------------------------------------------------------------
// Trellis.

TrellisEnergy cotton_trellis() { return TrellisEnergy(fitted_shear(cotton_shear()), kSigma, units::GramForce::PAPER); }

TEST(HandValues, TrellisLinearForce)
{
    // F = G phi_deg with G = 1 gf/(cm.deg), phi = 2 degrees, sigma = 2 cm:
    // T = 978.80e-7 J/(gf.cm) * sigma_cm^2 * integral_0^phi G (180/pi) psi cos(psi) dpsi
    //   = 978.80e-7 * 4 * (180/pi) (phi sin phi + cos phi - 1) = 1.36624634e-5 J
    // (small-angle G (180/pi) phi^2 / 2 * 4 * 978.80e-7 = 1.3667e-5 J).
    const TrellisEnergy t(smooth_curve(1.0, 0.0, 8.0), kSigma, units::GramForce::PAPER);
    const double phi = 2.0 * kPi / 180.0;
    EXPECT_NEAR(t.of_angle(phi).value, 1.3662463364216973e-05, 1.366e-5 * 1e-9);
    EXPECT_NEAR(t.of_angle(phi).value, 978.80e-7 * 4 * (180 / kPi) * (phi * std::sin(phi) + std::cos(phi) - 1), 1e-17);
    // dT/dphi = scale F(phi) cos(phi), F = 2 gf/cm.
    EXPECT_NEAR(t.of_angle(phi).d1, 978.80e-7 * 4 * 2.0 * std::cos(phi), 1e-18);
}

TEST(Trellis, ScaleMultipliesTheForceCurve)
{
    // ModelOptions::shear_scale: the law of the curve times the factor, singular continuation
    // included (it matches the scaled value and slope at phi_e).
    const TrellisEnergy one(smooth_curve(1.5, 0.02, 8.0), kSigma, units::GramForce::PAPER);
    const TrellisEnergy scaled(smooth_curve(1.5, 0.02, 8.0), kSigma, units::GramForce::PAPER, 1.0126);
    for (double phi : {-0.3, 0.01, 0.05, 0.1, 0.5, 1.0}) {
        EXPECT_NEAR(scaled.of_angle(phi).value, 1.0126 * one.of_angle(phi).value, 1e-12 * one.of_angle(phi).value) << phi;
        EXPECT_NEAR(scaled.of_angle(phi).d1, 1.0126 * one.of_angle(phi).d1, 1e-12 * std::abs(one.of_angle(phi).d1)) << phi;
        EXPECT_NEAR(scaled.of_angle(phi).d2, 1.0126 * one.of_angle(phi).d2, 1e-12 * std::abs(one.of_angle(phi).d2)) << phi;
    }
}

TEST(Trellis, ContinuousInValueAndSlopeAtLastMeasuredAngle)
{
    for (const TrellisEnergy& t : {cotton_trellis(), TrellisEnergy(smooth_curve(1.5, 0.02, 8.0), kSigma, units::GramForce::PAPER)}) {
        const double pe = t.last_measured_angle();
        EXPECT_NEAR(pe, 8.0 * kPi / 180.0, 1e-15);
        const Scalar3 in = t.of_angle(pe), out = t.of_angle(std::nextafter(pe, 2.0));
        EXPECT_NEAR(in.value, out.value, 1e-9 * in.value);
        EXPECT_NEAR(in.d1, out.d1, 1e-9 * in.d1);
        // The continuation is a/(1.05 - |phi|) + b.
        const double a = t.continuation_a(), b = t.continuation_b();
        EXPECT_GT(a, 0.0);
        EXPECT_NEAR(a / (1.05 - pe) + b, in.value, 1e-9 * in.value);
        EXPECT_NEAR(a / ((1.05 - pe) * (1.05 - pe)), in.d1, 1e-9 * in.d1);
        EXPECT_NEAR(t.of_angle(0.5).value, a / (1.05 - 0.5) + b, 1e-12 * t.of_angle(0.5).value);
        // negative side too
        EXPECT_NEAR(t.of_angle(-pe).d1, t.of_angle(std::nextafter(-pe, -2.0)).d1, 1e-9 * in.d1);
    }
}

TEST(Trellis, InfiniteAtAndPastSingularAngle)
{
    const TrellisEnergy t = cotton_trellis();
    for (double phi : {1.05, 1.0500001, 1.2, kPi / 2, -1.05, -1.3}) EXPECT_TRUE(std::isinf(t.of_angle(phi).value)) << phi;
    EXPECT_TRUE(std::isfinite(t.of_angle(1.0499).value));
    EXPECT_GT(t.of_angle(1.0499).value, 100 * t.of_angle(0.5).value);
    EXPECT_TRUE(std::isinf(t.of_cosine(-std::sin(1.06)).value));
    EXPECT_TRUE(std::isinf(t.of_cosine(1.0).value));
}

TEST(Trellis, EvenZeroAndFlatAtZero)
{
    const TrellisEnergy t = cotton_trellis();
    EXPECT_EQ(t.of_angle(0.0).value, 0.0);
    EXPECT_EQ(t.of_angle(0.0).d1, 0.0);
    EXPECT_GT(t.of_angle(0.0).d2, 0.0);
    for (double phi : {1e-6, 0.01, 0.1, 0.14, 0.3, 0.9, 1.04}) {
        EXPECT_EQ(t.of_angle(phi).value, t.of_angle(-phi).value);
        EXPECT_EQ(t.of_angle(phi).d1, -t.of_angle(-phi).d1);
        EXPECT_EQ(t.of_angle(phi).d2, t.of_angle(-phi).d2);
        EXPECT_GT(t.of_angle(phi).value, 0.0);
        EXPECT_EQ(t.of_cosine(-std::sin(phi)).value, t.of_cosine(std::sin(phi)).value);
    }
}

TEST(Trellis, AccurateAtSmallAngles)
{
    // Regression: T(phi) ~ scale F'(0) phi^2 / 2 keeps full relative precision as phi -> 0 (the
    // closed-form sin/cos primitives cancelled: T(1e-8) came out 0, T(1e-7) 1 % off).
    const kes::CurveFit F = fitted_shear(cotton_shear());
    const TrellisEnergy t(F, kSigma, units::GramForce::PAPER);
    const double k = 180.0 / kPi, B = F.segments()[0].c1 * k, C = F.segments()[0].c2 * k * k, scale = 4.0 * kPaperJoulePerGfCm;
    for (double phi : {1e-9, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4}) {
        // series of integral_0^phi (B psi + C psi^2)(1 - psi^2/2) dpsi, error ~ phi^6
        const double series = B * phi * phi / 2 + C * phi * phi * phi / 3 - B * std::pow(phi, 4) / 8 - C * std::pow(phi, 5) / 10;
        EXPECT_NEAR(t.of_angle(phi).value, scale * series, 1e-12 * scale * series) << phi;
    }
}

/// Composite 10-point Gauss-Legendre of F(psi) cos(psi) over [0, phi] with F fitted in degrees,
/// split at the fit's junctions and into 64 pieces each.
double quadrature(const kes::CurveFit& F, double phi)
{
    static const double x[5] = {0.1488743389816312, 0.4333953941292472, 0.6794095682990244, 0.8650633666889845, 0.9739065285171717};
    static const double w[5] = {0.2955242247147529, 0.2692667193099963, 0.2190863625159820, 0.1494513491505806, 0.0666713443086881};
    std::vector<double> cuts = {0.0};
    for (const kes::Segment& s : F.segments())
        if (s.x_end * kPi / 180 < phi) cuts.push_back(s.x_end * kPi / 180);
    cuts.push_back(phi);
    double total = 0;
    for (size_t i = 0; i + 1 < cuts.size(); ++i)
        for (int p = 0; p < 64; ++p) {
            const double a = cuts[i] + (cuts[i + 1] - cuts[i]) * p / 64, b = cuts[i] + (cuts[i + 1] - cuts[i]) * (p + 1) / 64;
            const double m = 0.5 * (a + b), r = 0.5 * (b - a);
            for (int q = 0; q < 5; ++q)
                for (double sgn : {-1.0, 1.0}) {
                    const double psi = m + sgn * r * x[q];
                    total += r * w[q] * F.value(psi * 180 / kPi) * std::cos(psi);
                }
        }
    return total;
}

TEST(Trellis, IntegralMatchesQuadratureOfTheFittedForce)
{
    for (const kes::ShearSummary& s : {cotton_shear(), kes::ShearSummary{0.5, 0.6, 1.2}, kes::ShearSummary{4.0, 6.0, 9.0}}) {
        const kes::CurveFit F = fitted_shear(s);
        const TrellisEnergy t(F, kSigma, units::GramForce::PAPER);
        const double scale = 4.0 * kPaperJoulePerGfCm;  // sigma_cm^2 * J per gf.cm
        for (double deg : {0.05, 0.3, 0.5, 1.0, 2.5, 5.0, 7.9, 8.0}) {
            const double phi = deg * kPi / 180;
            const double q = scale * quadrature(F, phi);
            EXPECT_NEAR(t.of_angle(phi).value, q, 1e-8 * q) << "G " << s.G << " phi " << deg << " deg";
        }
    }
}

class TrellisDerivatives : public testing::TestWithParam<double> {};  // phi (rad)

TEST_P(TrellisDerivatives, MatchFiniteDifferences)
{
    for (const TrellisEnergy& t : {cotton_trellis(), TrellisEnergy(smooth_curve(1.5, 0.02, 8.0), kSigma, units::GramForce::PAPER)}) {
        const double phi = GetParam();
        const double pe = t.last_measured_angle();
        // Step small against the distance to the seams (0, phi_e, 1.05) and to the fit's junctions.
        double room = std::min({std::abs(phi), std::abs(std::abs(phi) - pe), 1.05 - std::abs(phi)});
        for (const kes::Segment& s : t.force().segments()) room = std::min(room, std::abs(std::abs(phi) - s.x_end * kPi / 180));
        const double h = 1e-3 * room;
        auto fd = [&](auto f, double x) { return (8 * (f(x + h) - f(x - h)) - (f(x + 2 * h) - f(x - 2 * h))) / (12 * h); };
        const Scalar3 v = t.of_angle(phi);
        EXPECT_NEAR(fd([&](double p) { return t.of_angle(p).value; }, phi), v.d1, 1e-7 * std::abs(v.d1));
        EXPECT_NEAR(fd([&](double p) { return t.of_angle(p).d1; }, phi), v.d2, 1e-7 * std::abs(v.d2));
        // of_cosine, c = -sin(phi)
        const double c = -std::sin(phi);
        const double hc = h * std::cos(phi);
        const Scalar3 w = t.of_cosine(c);
        EXPECT_EQ(w.value, v.value);
        auto fdc = [&](auto f) { return (8 * (f(c + hc) - f(c - hc)) - (f(c + 2 * hc) - f(c - 2 * hc))) / (12 * hc); };
        EXPECT_NEAR(fdc([&](double x) { return t.of_cosine(x).value; }), w.d1, 1e-7 * std::abs(w.d1));
        EXPECT_NEAR(fdc([&](double x) { return t.of_cosine(x).d1; }), w.d2, 1e-7 * std::abs(w.d2));
    }
}
INSTANTIATE_TEST_SUITE_P(Sweep, TrellisDerivatives,
                         testing::Values(1e-4, -1e-3, 0.003, 0.02, -0.05, 0.1, 0.1396, 0.1397, -0.15, 0.3, 0.6, -0.9, 1.0, 1.04));

}  // namespace
}  // namespace woven::test
