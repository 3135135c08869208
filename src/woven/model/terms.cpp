#include "woven/model/terms.hpp"

#include <algorithm>
#include <limits>

#include "woven/model/angle.hpp"

namespace woven::model {

const char* term_name(Term term)
{
    switch (term) {
    case Term::GRAVITY: return "gravity";
    case Term::STRETCH: return "stretch";
    case Term::REPULSION: return "repulsion";
    case Term::BENDING_WARP: return "bending_warp";
    case Term::BENDING_WEFT: return "bending_weft";
    case Term::TRELLIS: return "trellis";
    case Term::TWIST: return "twist";
    case Term::SEAM: return "seam";
    }
    return "?";
}

namespace {

Local<2> vanishing_pair()
{
    Local<2> l;
    l.vanishes = true;
    return l;
}

/// A two-particle term f(r), d = x0 - x1, r = |d|. In PROJECTED mode the Hessian
/// f'' n n^T + (f'/r)(I - n n^T) is clamped per eigenvalue (exact PSD projection).
Local<2> pair_local(const Scalar3& f, const Vec3& d, double r, Derivatives what)
{
    Local<2> l;
    l.value = f.value;
    if (what == Derivatives::NONE || !std::isfinite(f.value)) return l;
    const Vec3 n = d / r;
    l.gradient << f.d1 * n, -f.d1 * n;
    if (!wants_hessian(what)) return l;
    const bool project = what == Derivatives::PROJECTED;
    const double along = project ? std::max(f.d2, 0.0) : f.d2;
    const double across = project ? std::max(f.d1 / r, 0.0) : f.d1 / r;
    const Mat3 nn = n * n.transpose();
    const Mat3 h = along * nn + across * (Mat3::Identity() - nn);
    l.hessian << h, -h, -h, h;
    return l;
}

/// An angle term f(c), c = cos(angle between a and b): value, and gradient and Hessian in (a, b).
struct AngleLocal {
    double value = 0;
    bool derivatives = false;  ///< g (and H when asked) are set
    VecN<6> g;
    MatN<6> H;
};

/// `gauss_newton_bending`: the projected Hessian's second part, max(f', 0) J^T J (bending), or
/// none (trellis).
template <class Energy> AngleLocal angle_local(const Energy& energy, const Vec3& a, const Vec3& b, Derivatives what, bool gauss_newton_bending)
{
    const bool project = what == Derivatives::PROJECTED;
    const CosineDerivatives cd = cosine_between(a, b, wants_hessian(what) && !project);
    const Scalar3 f = energy.of_cosine(cd.c);
    AngleLocal out;
    out.value = f.value;
    if (what == Derivatives::NONE || !std::isfinite(f.value)) return out;
    out.derivatives = true;
    out.g = f.d1 * cd.gradient;
    if (!wants_hessian(what)) return out;
    if (!project)
        out.H = f.d2 * cd.gradient * cd.gradient.transpose() + f.d1 * cd.hessian;
    else if (gauss_newton_bending)  // f'' >= 0 part of grad c grad c^T, and J^T J in place of c's Hessian (f' >= 0)
        out.H = std::max(f.d2, 0.0) * cd.gradient * cd.gradient.transpose() + std::max(f.d1, 0.0) * bending_gauss_newton(a, b);
    else  // drops f' times c's (indefinite) Hessian; exact at phi = 0 where f' = 0
        out.H = std::max(f.d2, 0.0) * cd.gradient * cd.gradient.transpose();
    return out;
}

template <int N> Local<N> to_local(const AffinePair<N>& stencil, const AngleLocal& a, Derivatives what)
{
    Local<N> l;
    l.value = a.value;
    if (!a.derivatives) return l;
    l.gradient = to_particles<N>(stencil, a.g);
    if (wants_hessian(what)) l.hessian = to_particles<N>(stencil, a.H);
    return l;
}

template <int N> ParticleLocal to_particle_local(const AffinePair<N>& stencil, const AngleLocal& a, int k, Derivatives what)
{
    ParticleLocal p;
    p.value = a.value;
    if (!a.derivatives) return p;
    p.gradient = to_particle<N>(stencil, a.g, k);
    if (wants_hessian(what)) p.hessian = to_particle_block<N>(stencil, a.H, k);
    return p;
}

AngleLocal bending_local(const BendingEnergy& energy, const VecN<9>& x, Derivatives what)
{
    const Vec3 x1 = x.segment<3>(3);
    return angle_local(energy, Vec3(x.head<3>() - x1), Vec3(x.tail<3>() - x1), what, true);
}

AngleLocal trellis_local(const TrellisEnergy& energy, const VecN<12>& x, Derivatives what)
{
    return angle_local(energy, Vec3(x.segment<3>(3) - x.head<3>()), Vec3(x.tail<3>() - x.segment<3>(6)), what, false);
}

}  // namespace

Local<1> GravityTerm::evaluate(const VecN<3>& x, Derivatives what) const
{
    Local<1> l;
    l.value = weight_ * x.z();
    if (what == Derivatives::NONE) return l;
    l.gradient = Vec3(0, 0, weight_);
    if (wants_hessian(what)) l.hessian.setZero();
    return l;
}

Local<2> StretchTerm::evaluate(const VecN<6>& x, Derivatives what) const
{
    const Vec3 d = x.head<3>() - x.tail<3>();
    const double r = d.norm();
    if (r <= spacing_.sigma && !(spacing_.tensile > 0)) return vanishing_pair();  // the paper's well: tension only
    if (r == 0) return pair_local(Scalar3{0.5 * spacing_.tensile * spacing_.sigma * spacing_.sigma, 0, 0}, Vec3::UnitX(), 1.0, what);
    return pair_local(spacing_.stretch(r), d, r, what);
}

Local<2> RepulsionTerm::evaluate(const VecN<6>& x, Derivatives what) const
{
    const Vec3 d = x.head<3>() - x.tail<3>();
    const double r = d.norm();
    if (r >= spacing_.sigma) return vanishing_pair();
    return pair_local(spacing_.repulsion(r), d, r, what);
}

Local<3> BendingTerm::evaluate(const VecN<9>& x, Derivatives what) const
{
    return to_local<3>(kBendingStencil, bending_local(energy_, x, what), what);
}

ParticleLocal BendingTerm::particle(const VecN<9>& x, int k, Derivatives what) const
{
    return to_particle_local<3>(kBendingStencil, bending_local(energy_, x, what), k, what);
}

Local<4> TrellisTerm::evaluate(const VecN<12>& x, Derivatives what) const
{
    return to_local<4>(kTrellisStencil, trellis_local(energy_, x, what), what);
}

ParticleLocal TrellisTerm::particle(const VecN<12>& x, int k, Derivatives what) const
{
    return to_particle_local<4>(kTrellisStencil, trellis_local(energy_, x, what), k, what);
}

namespace {

Mat3 cross_matrix(const Vec3& a)
{
    Mat3 m;
    m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
    return m;
}

}  // namespace

double TwistTerm::twist_height(const VecN<12>& x)
{
    const Vec3 m = Vec3(x.segment<3>(9) - x.head<3>()).cross(Vec3(x.segment<3>(6) - x.segment<3>(3)));
    const double s = m.norm();
    if (!(s > 0)) return std::numeric_limits<double>::quiet_NaN();
    return Vec3(x.head<3>() - x.segment<3>(3) - x.segment<3>(6) + x.segment<3>(9)).dot(m) / s;
}

Local<4> TwistTerm::evaluate(const VecN<12>& x, Derivatives what) const
{
    using Mat3x12 = Eigen::Matrix<double, 3, 12>;
    const Vec3 x0 = x.head<3>(), x1 = x.segment<3>(3), x2 = x.segment<3>(6), x3 = x.segment<3>(9);
    const Vec3 h = x0 - x1 - x2 + x3, e1 = x3 - x0, e2 = x2 - x1;
    const Vec3 m = e1.cross(e2);
    const double s = m.norm();
    Local<4> l;
    if (!(s > 0)) {
        l.value = std::numeric_limits<double>::infinity();
        return l;
    }
    const Vec3 u = m / s;
    const double f = h.dot(u);
    l.value = k_ * f * f;
    if (what == Derivatives::NONE) return l;
    // h = S x, e1 = D1 x, e2 = D2 x; dm = J dx with J = [e1]x D2 - [e2]x D1.
    const Mat3 I = Mat3::Identity(), E1 = cross_matrix(e1), E2 = cross_matrix(e2);
    Mat3x12 S, D1, D2, J;
    S << I, -I, -I, I;
    D1 << -I, Mat3::Zero(), Mat3::Zero(), I;
    D2 << Mat3::Zero(), -I, I, Mat3::Zero();
    J << E2, -E1, E1, -E2;
    // f = q / s, q = h.m, s = |m|.
    const VecN<12> grad_q = S.transpose() * m + J.transpose() * h;
    const VecN<12> grad_s = J.transpose() * u;
    const VecN<12> grad_f = (grad_q - f * grad_s) / s;
    l.gradient = 2 * k_ * f * grad_f;
    if (!wants_hessian(what)) return l;
    if (what == Derivatives::PROJECTED) {
        l.hessian = 2 * k_ * grad_f * grad_f.transpose();
        return l;
    }
    // Second derivatives of the bilinear m contracted with a vector v: -D1^T [v]x D2 + transpose.
    auto contracted = [&](const Vec3& v) {
        const MatN<12> K = -D1.transpose() * cross_matrix(v) * D2;
        return MatN<12>(K + K.transpose());
    };
    const MatN<12> SJ = S.transpose() * J;
    const MatN<12> hess_q = SJ + SJ.transpose() + contracted(h);
    const MatN<12> hess_s = J.transpose() * (I - u * u.transpose()) * J / s + contracted(u);
    const MatN<12> hess_f = (hess_q - f * hess_s - grad_f * grad_s.transpose() - grad_s * grad_f.transpose()) / s;
    l.hessian = 2 * k_ * (grad_f * grad_f.transpose() + f * hess_f);
    return l;
}

}  // namespace woven::model
