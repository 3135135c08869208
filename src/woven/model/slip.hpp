#pragma once
// Friction inside the weave (the paper's Sec. 7): bending and shear are hysteretic because the
// threads slip against each other where they cross. Each bend (warp and weft bending stencils)
// and each crossing (trellis stencil) carries kSlipElements Jenkins elements in parallel with
// the elastic energy (energy_functions.hpp, which in this mode carries the mean line of slope B
// or G): element e is a spring of stiffness k in series with a friction slider of threshold
// m_e(q), with slip state s_e, on the local strain q:
//
//   bends:     q = signed curvature (1/cm) = (a/|a| + b/|b|) . n / sigma_cm,
//              a = x0 - x1, b = x2 - x1 along the thread, n the unit normal of the cloth there,
//              n = w x (x2 - x0) (warp bends) or (x2 - x0) x w (weft bends), w = x4 - x3 the
//              chord across the thread (the two neighbours across, one of them the bend's own
//              middle particle at a free edge): on a bent specimen (KES-FB2) q = +-K exactly,
//              the sign saying to which side the thread bends (a three-particle bend has none);
//   crossings: q = sin(phi) = -c (terms.hpp), so that dE/dphi = F cos(phi), the trellis
//              energy's own form (Eq. 14-15).
//
// Element e's force is the return mapping of its trial state scaled by the family's amplitude,
// F_e(q) = g(q) clamp(k (q - s_e), -m_e, +m_e), s_e the state of the last converged step, and
// the step's energy is its integral from s_e, E_e(q) = integral_{s_e}^{q} F_e. For bending g = 1
// and E_e is the condensed convex C1 form min_s [k (q - s)^2 / 2 + m_e |s - s_e|], the Huber
// function of q - s_e: k d^2/2 for |d| <= m_e/k, m_e |d| - m_e^2/(2k) beyond. The KES shear widths
// differ at 0.5 and 5 degrees (2HG, 2HG5: the yarns jam and press harder), so for shear the
// amplitude g(q) = h(|q|) / h_ref grows (or falls) linearly with |q|: E_e is then C1 and piecewise
// cubic, its second derivative g' J + g J' (J' = k or 0), g' small against the elastic G; the
// slip itself (s_e) and each element's yield strain m_e / k do not depend on g. Every solver step
// thus stays a smooth minimisation; after a converged step update_slip sets s_e = q - J_e(q)/k
// (the return mapping), reset_slip the virgin state 0.
//
// The elements' thresholds are graded (m_e = w_e h_ref, w_e = 2 (e + 1/2) / N^2, equal k =
// 2 h_ref / (q1 N)), so that the virgin friction rises as h(|q|) r(q / q1), r(u) = 1 - (1 - u)^2
// (the rise of the synthesised KES curves, kes/fabric.hpp), by N linear pieces, and a reversal
// follows Masing's rule (the virgin rise stretched twice): a loop's half width is h(|q|), 2HB/2
// at 1 1/cm for bending, linear through 2HG/2 at 0.5 and 2HG5/2 at 5 degrees for shear.
#include <array>
#include <vector>

#include "woven/common/choice.hpp"
#include "woven/common/types.hpp"
#include "woven/model/energy_functions.hpp"
#include "woven/model/terms.hpp"

namespace woven::model {

/// How the KES hysteresis enters the model (ModelOptions::hysteresis).
enum class Hysteresis {
    /// The loading branch of each curve as an elastic energy (the friction pushes back like a
    /// spring: docs/FABRIC-FORMAT.md).
    LOADING_BRANCH,
    /// The mean line as the elastic energy plus Jenkins friction elements (this file), for the
    /// curves given by summary values with a hysteresis width; curves given as points keep
    /// their loading branch.
    FRICTION,
};

/// The modes' names: "loading-branch", "friction" (scene files, the command line, reports).
inline constexpr std::array<Named<Hysteresis>, 2> kHysteresisNames{{{Hysteresis::LOADING_BRANCH, "loading-branch"},
                                                                    {Hysteresis::FRICTION, "friction"}}};
/// Its name in kHysteresisNames.
const char* to_string(Hysteresis h);

/// Jenkins elements per bend or crossing.
inline constexpr int kSlipElements = 8;
/// One bend's or crossing's slip states s_e (q units).
using SlipState = std::array<double, kSlipElements>;

/// The Jenkins elements of one family (warp bends, weft bends or crossings), in the KES units
/// of its curve: q in 1/cm (bending) or sin(phi) (shear), forces in gf.cm/cm or gf/cm.
struct SlipLaw {
    double h0 = 0;  ///< the loop's half width h(|q|) = max(h0 + dh |q|, 0)
    double dh = 0;
    double h_ref = 0;  ///< the half width the thresholds are set for: g(q) = h(|q|) / h_ref
    double k = 0;      ///< each element's stiffness (force per unit q); 0: no friction
    std::array<double, kSlipElements> share{};  ///< w_e, summing to 1
    double scale = 0;  ///< J per (force unit x q unit), set by the model: sigma_cm^2 J/(gf.cm)

    bool active() const { return k > 0; }
    double half_width(double q) const;
    /// g(q) and dg/dq.
    double amplitude(double q) const { return half_width(q) / h_ref; }
    double amplitude_slope(double q) const;
    /// m_e = w_e h_ref.
    double threshold(int e) const { return share[e] * h_ref; }
    /// J_e(q) = clamp(k (q - s), -m_e, m_e), the element's unscaled force.
    double jenkins(int e, double q, double s) const;
    /// F_e(q) = g(q) J_e(q).
    double force(int e, double q, double s) const { return amplitude(q) * jenkins(e, q, s); }
    /// E_e(q) = integral_s^q F_e, F_e(q), dF_e/dq (in force x q units, not scaled).
    Scalar3 element(int e, double q, double s) const;
    /// The sum over the elements of `state`, scaled to J (value, dE/dq, d2E/dq2).
    Scalar3 energy(double q, const SlipState& state) const;
    /// The return mapping: each s_e = q - J_e(q)/k.
    void update(double q, SlipState& state) const;
    /// The total friction force sum_e F_e(q) (force units).
    double total_force(double q, const SlipState& state) const;
};

/// A law whose half width is linear through (q_a, h_a) and (q_b, h_b) (constant when q_a ==
/// q_b; a line that would pass below 0 at q = 0 is taken through the origin and (q_b, h_b)),
/// h_ref = its half width at q_a, and whose virgin friction saturates at q1.
/// h_a = h_b = 0: an inactive law.
SlipLaw make_slip_law(double q_a, double h_a, double q_b, double h_b, double q1);

/// The three families' laws, KES units (scale unset).
struct SlipLaws {
    SlipLaw warp, weft, shear;
    bool any() const { return warp.active() || weft.active() || shear.active(); }
};

/// Signed curvature of a five-particle bend (x0 x1 x2 along the thread, x3 x4 across it) with
/// its gradient and Hessian (15 unknowns), or only the value. `weft`: n = (x2 - x0) x w.
/// `ok` false where the normal or a segment vanishes (the term is then 0).
struct SignedCurvature {
    double q = 0;
    bool ok = false;
    VecN<15> gradient = VecN<15>::Zero();
    MatN<15> hessian = MatN<15>::Zero();
};
SignedCurvature signed_curvature(const VecN<15>& x, double sigma_cm, bool weft, bool derivatives);

/// The friction of one bend: x0 x1 x2 along the thread, x3 x4 across it (stencils.hpp,
/// Stencils::warp_slip_bends). PROJECTED: the exact Hessian with its negative eigenvalues
/// clamped at 0 (an exact PSD projection).
class SlipBendTerm {
public:
    static constexpr int kParticles = 5;
    SlipBendTerm(const SlipLaw& law, double sigma_cm, bool weft) : law_(law), sigma_cm_(sigma_cm), weft_(weft) { }
    Local<5> evaluate(const VecN<15>& x, const SlipState& state, Derivatives what) const;
    /// q, the signed curvature (1/cm); 0 where it is not defined.
    double strain(const VecN<15>& x) const;

private:
    const SlipLaw& law_;
    double sigma_cm_;
    bool weft_;
};

/// The friction of one crossing (the trellis stencil L R D U, terms.hpp), q = sin(phi) = -c.
/// PROJECTED as SlipBendTerm.
class SlipTrellisTerm {
public:
    static constexpr int kParticles = 4;
    explicit SlipTrellisTerm(const SlipLaw& law) : law_(law) { }
    Local<4> evaluate(const VecN<12>& x, const SlipState& state, Derivatives what) const;
    double strain(const VecN<12>& x) const;

private:
    const SlipLaw& law_;
};

/// The closest positive semi-definite matrix (eigenvalues clamped at 0).
template <int N> MatN<N> psd_projection(const MatN<N>& H);

}  // namespace woven::model
