#pragma once
// The terms of Eq. (1), each a function on its own fixed-size stencil (stencils.hpp) with value,
// gradient and Hessian (exact, or projected to positive semi-definite for Newton's method) in
// fixed-size Eigen types. Each term is written here once; ClothModel sums them over their
// stencil lists and the paper solver takes its per-particle blocks from them.
//
// Positions of an N-particle stencil: x = (x0, ..., x_{N-1}), a 3N vector (m). Energies in J,
// gradients in J/m, Hessians in J/m^2. A term is +inf in a singular configuration (trellis at or
// past 1.05 rad, a thread folded to theta = 0, two particles at the same place): then no
// derivatives are computed and the caller must reject the configuration.
#include <cmath>
#include <concepts>

#include "woven/common/types.hpp"
#include "woven/model/energy_functions.hpp"
#include "woven/model/stencils.hpp"

namespace woven::model {

/// What is computed besides the value.
enum class Derivatives {
    NONE,       ///< value only
    GRADIENT,   ///< value and gradient
    HESSIAN,    ///< + the exact Hessian
    PROJECTED,  ///< + a positive semi-definite Hessian (per term below)
};

/// True when a Hessian (exact or projected) is asked for.
inline bool wants_hessian(Derivatives what) { return what == Derivatives::HESSIAN || what == Derivatives::PROJECTED; }

/// The terms of Eq. (1); EnergyTerms has one field per term.
/// TWIST is beyond the paper: the bias bending of docs/MODEL.md ("The bias term"), TwistTerm.
/// SEAM is beyond the paper too: the stitches of a garment's seams (seams.hpp, SeamTerm).
enum class Term { GRAVITY, STRETCH, REPULSION, BENDING_WARP, BENDING_WEFT, TRELLIS, TWIST, SEAM };
inline constexpr Term kAllTerms[] = {Term::GRAVITY, Term::STRETCH, Term::REPULSION, Term::BENDING_WARP, Term::BENDING_WEFT, Term::TRELLIS, Term::TWIST, Term::SEAM};
/// "gravity", "stretch", "repulsion", "bending_warp", "bending_weft", "trellis", "twist", "seam".
const char* term_name(Term term);

/// One term on one N-particle stencil.
template <int N> struct Local {
    double value = 0;       ///< J
    bool vanishes = false;  ///< value and derivatives are zero here (outside the term's support)
    VecN<3 * N> gradient;   ///< dE/dx (J/m); set for GRADIENT and up, unless vanishes or infinite
    MatN<3 * N> hessian;    ///< d2E/dx2 (J/m^2); set for HESSIAN and PROJECTED, likewise
};

/// Particle k's share of a term on a stencil, for per-particle (Gauss-Seidel) steps.
struct ParticleLocal {
    double value = 0;  ///< the term's value (J)
    Vec3 gradient;     ///< dE/dx_k; set as Local's
    Mat3 hessian;      ///< the k-k block of the (exact or projected) Hessian
};

/// The stencil's positions gathered from all positions.
template <int N> VecN<3 * N> gather(const Positions& x, const Stencil<N>& s)
{
    VecN<3 * N> out;
    for (int k = 0; k < N; ++k) out.template segment<3>(3 * k) = x[s[k]];
    return out;
}

/// value, gradient, hessian and particle of a term T on N particles, from T::evaluate (CRTP).
template <class T, int N> class TermFunctions {
public:
    static constexpr int kParticles = N;
    using X = VecN<3 * N>;  ///< the stencil's positions

    double value(const X& x) const { return self().evaluate(x, Derivatives::NONE).value; }
    VecN<3 * N> gradient(const X& x) const { return derivative(x, Derivatives::GRADIENT).gradient; }
    MatN<3 * N> hessian(const X& x, bool projected = false) const
    {
        return derivative(x, projected ? Derivatives::PROJECTED : Derivatives::HESSIAN).hessian;
    }
    /// Particle k's value, gradient and Hessian block (terms with a cheaper way hide this).
    ParticleLocal particle(const X& x, int k, Derivatives what) const
    {
        const Local<N> l = self().evaluate(x, what);
        ParticleLocal p;
        p.value = l.value;
        if (what == Derivatives::NONE || !std::isfinite(l.value)) return p;
        p.gradient = l.vanishes ? Vec3::Zero() : Vec3(l.gradient.template segment<3>(3 * k));
        if (what != Derivatives::GRADIENT) p.hessian = l.vanishes ? Mat3::Zero() : Mat3(l.hessian.template block<3, 3>(3 * k, 3 * k));
        return p;
    }

private:
    const T& self() const { return static_cast<const T&>(*this); }
    Local<N> derivative(const X& x, Derivatives what) const
    {
        Local<N> l = self().evaluate(x, what);
        if (l.vanishes) {
            l.gradient.setZero();
            l.hessian.setZero();
        }
        return l;
    }
};

/// Gravity of one particle (Eq. 6), mass m (kg), gravity g (m/s^2) along -z:
///
///     x0        G = m g z0                          (J)
///
/// Linear: its Hessian is zero (and PSD).
class GravityTerm : public TermFunctions<GravityTerm, 1> {
public:
    GravityTerm(double mass, double gravity) : weight_(mass * gravity) { }
    Local<1> evaluate(const VecN<3>& x, Derivatives what) const;

private:
    double weight_;  ///< m g (N)
};

/// Stretching of one thread segment (Eq. 3, 5), on a 4-connected pair:
///
///     x0 -------- x1        r = |x0 - x1|,  S(r) = C0 ((r - sigma)/sigma)^5 for r > sigma, else 0
///
/// (ThreadSpacing::stretch). Projected Hessian: S'' n n^T + (S'/r)(I - n n^T), n = (x0 - x1)/r,
/// each eigenvalue clamped at 0 (an exact PSD projection; S', S'' >= 0, so equal to the exact).
class StretchTerm : public TermFunctions<StretchTerm, 2> {
public:
    explicit StretchTerm(const ThreadSpacing& spacing) : spacing_(spacing) { }
    Local<2> evaluate(const VecN<6>& x, Derivatives what) const;

private:
    ThreadSpacing spacing_;
};

/// Repulsion of two particles closer than sigma (Eq. 2, 4), any pair of the cloth:
///
///     x0 ..... x1           r = |x0 - x1|,  R(r) = C0 ((sigma - r)/sigma)^5 (sigma/r) for r < sigma
///
/// (ThreadSpacing::repulsion). Projected Hessian as StretchTerm's (here R' < 0: the part across
/// n is clamped to 0).
class RepulsionTerm : public TermFunctions<RepulsionTerm, 2> {
public:
    explicit RepulsionTerm(const ThreadSpacing& spacing) : spacing_(spacing) { }
    Local<2> evaluate(const VecN<6>& x, Derivatives what) const;

private:
    ThreadSpacing spacing_;
};

/// Bending of one thread angle (Eq. 7, 12, corrected 13), on three particles along a thread
/// (warp or weft: the energy function says which curve):
///
///     x0 -------- x1 -------- x2      a = x0 - x1, b = x2 - x1, c = cos(theta) = a.b/(|a||b|)
///                 theta at x1 (pi when straight)
///
/// B = BendingEnergy::of_cosine(c) (J). Projected Hessian (Gauss-Newton): max(B'', 0) grad c
/// grad c^T + max(B', 0) J^T J, J = d(a/|a| + b/|b|)/d(a, b) (angle.hpp), which equals the exact
/// Hessian at a straight thread.
class BendingTerm : public TermFunctions<BendingTerm, 3> {
public:
    explicit BendingTerm(const BendingEnergy& energy) : energy_(energy) { }
    Local<3> evaluate(const VecN<9>& x, Derivatives what) const;
    ParticleLocal particle(const VecN<9>& x, int k, Derivatives what) const;

private:
    const BendingEnergy& energy_;
};

/// Trellising of one thread crossing (Eq. 8, 15), on the four neighbours of a particle k:
///
///                  x3 = U
///                   |
///     x0 = L ------ k ------ x1 = R     u = R - L, v = U - D, c = u.v/(|u||v|) = -sin(phi)
///                   |
///                  x2 = D               (phi does not depend on k itself)
///
/// T = TrellisEnergy::of_cosine(c) (J), even in phi. Projected Hessian (Gauss-Newton):
/// max(T'', 0) grad c grad c^T, dropping T' times c's indefinite Hessian (exact at phi = 0,
/// where T' = 0).
class TrellisTerm : public TermFunctions<TrellisTerm, 4> {
public:
    explicit TrellisTerm(const TrellisEnergy& energy) : energy_(energy) { }
    Local<4> evaluate(const VecN<12>& x, Derivatives what) const;
    ParticleLocal particle(const VecN<12>& x, int k, Derivatives what) const;

private:
    const TrellisEnergy& energy_;
};

/// Twisting of one grid cell (beyond the paper: the bias bending of docs/MODEL.md), on its corners:
///
///     x2 = (i,j+1) ---- x3 = (i+1,j+1)    h = x0 - x1 - x2 + x3 (zero for any parallelogram)
///       |                  |              n = (x3 - x0) x (x2 - x1) / |.|, the diagonals' normal
///     x0 = (i,j)  ----- x1 = (i+1,j)      f = h.n = sigma^2 tau, tau = d2w/du dv the twist
///
/// E = T f^2 / (2 sigma^2) (J): the energy T tau^2 / 2 per unit area of a sigma x sigma cell, T the
/// twisting rigidity (N m) of an orthotropic plate's 2 (D12 + 2 D66). A bend of curvature k at
/// angle a to the warp has tau = k cos(a) sin(a): E vanishes for bends along either thread and for
/// in-plane shear and adds T k^2 cos^2 sin^2 / 2 between them. +inf when the diagonals are parallel.
/// Projected Hessian (Gauss-Newton): (T / sigma^2) grad f grad f^T.
class TwistTerm : public TermFunctions<TwistTerm, 4> {
public:
    /// `rigidity` T in N m (J), `sigma` the rest spacing (m).
    TwistTerm(double rigidity, double sigma) : k_(0.5 * rigidity / (sigma * sigma)) { }
    Local<4> evaluate(const VecN<12>& x, Derivatives what) const;
    /// f = h.n (m), the cell's twist times sigma^2; NaN when the diagonals are parallel.
    static double twist_height(const VecN<12>& x);

private:
    double k_;  ///< T / (2 sigma^2), J/m^2
};

/// A term's local value and derivatives times a weight (the share of cloth its stencil stands
/// for, stencils.hpp).
template <int N> void scale_local(Local<N>& l, double w)
{
    l.value *= w;
    if (l.vanishes) return;
    l.gradient *= w;
    l.hessian *= w;
}
inline void scale_local(ParticleLocal& l, double w)
{
    l.value *= w;
    l.gradient *= w;
    l.hessian *= w;
}

// ---------------------------------------------------------------------------------------------
// Local to global: a sink receives each stencil's local derivatives and scatters them.

/// The concept of a sink for ClothModel::evaluate: `add<N>(term, ids, local, with_hessian)`.
template <class S>
concept LocalSink = requires(S& s, const Stencil<2>& ids, const Local<2>& l) { s.template add<2>(Term::STRETCH, ids, l, true); };

/// A sink whose adds can be split into parts() parts run at once: add<N>(..., part) adds only
/// what part `part` owns, each value owned by one part, so that every value receives its
/// stencils' contributions in their order whatever the number of parts.
template <class S>
concept PartitionedSink = LocalSink<S> && requires(S& s, const Stencil<2>& ids, const Local<2>& l) {
    { s.parts() } -> std::convertible_to<int>;
    s.template add<2>(Term::STRETCH, ids, l, true, 0);
};

/// Adds a stencil's local gradient into a global 3n vector (particle p at 3p).
template <int N> void add_local_gradient(const Stencil<N>& ids, const VecN<3 * N>& local, Eigen::VectorXd& global)
{
    for (int k = 0; k < N; ++k) global.template segment<3>(3 * ids[k]) += local.template segment<3>(3 * k);
}

/// A sink that assembles the gradient only.
struct GradientSink {
    Eigen::VectorXd& gradient;
    template <int N> void add(Term, const Stencil<N>& ids, const Local<N>& l, bool) { add_local_gradient<N>(ids, l.gradient, gradient); }
};

}  // namespace woven::model
