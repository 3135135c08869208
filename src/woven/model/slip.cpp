#include "woven/model/slip.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "woven/model/angle.hpp"

namespace woven::model {

const char* to_string(Hysteresis h) { return name_of(kHysteresisNames, h); }

// ---------------------------------------------------------------------------------------------
// The Jenkins elements

double SlipLaw::half_width(double q) const { return std::max(h0 + dh * std::abs(q), 0.0); }

double SlipLaw::amplitude_slope(double q) const
{
    if (!(h0 + dh * std::abs(q) > 0)) return 0;
    return dh * (q > 0 ? 1.0 : (q < 0 ? -1.0 : 0.0)) / h_ref;
}

double SlipLaw::jenkins(int e, double q, double s) const
{
    const double m = threshold(e);
    return std::clamp(k * (q - s), -m, m);
}

Scalar3 SlipLaw::element(int e, double q, double s) const
{
    // F = g J is the product of two piecewise linear functions: J's kinks are at s +- m_e/k,
    // g's at 0 and where h reaches 0. Between them F is quadratic and Simpson's rule exact.
    const double m = threshold(e);
    const double lo = std::min(q, s), hi = std::max(q, s);
    double points[8];
    int n = 0;
    points[n++] = lo;
    auto add = [&](double t) {
        if (t > lo && t < hi) points[n++] = t;
    };
    add(0.0);
    if (dh < 0 && h0 > 0) {
        add(h0 / -dh);
        add(h0 / dh);
    }
    add(s - m / k);
    add(s + m / k);
    points[n++] = hi;
    for (int i = 1; i < n; ++i)  // insertion sort of at most 7 points
        for (int j = i; j > 0 && points[j - 1] > points[j]; --j) std::swap(points[j - 1], points[j]);
    double integral = 0;
    for (int i = 0; i + 1 < n; ++i) {
        const double a = points[i], b = points[i + 1];
        integral += (b - a) / 6.0 * (force(e, a, s) + 4.0 * force(e, 0.5 * (a + b), s) + force(e, b, s));
    }
    Scalar3 out;
    out.value = q >= s ? integral : -integral;
    const double J = jenkins(e, q, s);
    out.d1 = amplitude(q) * J;
    const double dJ = std::abs(k * (q - s)) < m ? k : 0.0;
    out.d2 = amplitude_slope(q) * J + amplitude(q) * dJ;
    return out;
}

Scalar3 SlipLaw::energy(double q, const SlipState& state) const
{
    Scalar3 total;
    for (int e = 0; e < kSlipElements; ++e) {
        const Scalar3 el = element(e, q, state[e]);
        total.value += el.value;
        total.d1 += el.d1;
        total.d2 += el.d2;
    }
    return {scale * total.value, scale * total.d1, scale * total.d2};
}

void SlipLaw::update(double q, SlipState& state) const
{
    for (int e = 0; e < kSlipElements; ++e) state[e] = q - jenkins(e, q, state[e]) / k;
}

double SlipLaw::total_force(double q, const SlipState& state) const
{
    double f = 0;
    for (int e = 0; e < kSlipElements; ++e) f += force(e, q, state[e]);
    return f;
}

SlipLaw make_slip_law(double q_a, double h_a, double q_b, double h_b, double q1)
{
    SlipLaw law;
    if (!(h_a > 0) && !(h_b > 0)) return law;
    if (q_b != q_a) {
        law.dh = (h_b - h_a) / (q_b - q_a);
        law.h0 = h_a - law.dh * q_a;
        if (law.h0 < 0) {  // a line through 0 or below: through (q_b, h_b) and the origin
            law.h0 = 0;
            law.dh = h_b / q_b;
        }
    } else
        law.h0 = h_a;
    law.h_ref = law.half_width(q_a);
    if (!(law.h_ref > 0)) law.h_ref = law.half_width(q_b);
    law.k = 2.0 * law.h_ref / (q1 * kSlipElements);
    for (int e = 0; e < kSlipElements; ++e) law.share[e] = 2.0 * (e + 0.5) / (kSlipElements * kSlipElements);
    return law;
}

// ---------------------------------------------------------------------------------------------
// The signed curvature, with first and second derivatives by forward-mode hyper-dual numbers
// over the nine unknowns (a, b, w): exact to rounding.

namespace {

struct D {
    double v = 0;
    VecN<9> g = VecN<9>::Zero();
    MatN<9> h = MatN<9>::Zero();
};
D operator+(const D& x, const D& y) { return {x.v + y.v, x.g + y.g, x.h + y.h}; }
D operator-(const D& x, const D& y) { return {x.v - y.v, x.g - y.g, x.h - y.h}; }
D operator*(const D& x, const D& y)
{
    return {x.v * y.v, x.g * y.v + y.g * x.v, x.h * y.v + y.h * x.v + x.g * y.g.transpose() + y.g * x.g.transpose()};
}
D operator*(double c, const D& x) { return {c * x.v, c * x.g, c * x.h}; }
/// f(x) for a scalar f with f(x.v) = f0, f'(x.v) = f1, f''(x.v) = f2.
D chain(const D& x, double f0, double f1, double f2) { return {f0, f1 * x.g, f1 * x.h + f2 * x.g * x.g.transpose()}; }
D inv_sqrt(const D& x)
{
    const double r = 1.0 / std::sqrt(x.v);
    return chain(x, r, -0.5 * r / x.v, 0.75 * r / (x.v * x.v));
}
using V = std::array<D, 3>;
D dot(const V& x, const V& y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; }
V cross(const V& x, const V& y) { return {x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]}; }
V scaled(const V& x, const D& c) { return {x[0] * c, x[1] * c, x[2] * c}; }

/// Coefficients of the five particles in a = x0 - x1, b = x2 - x1, w = x4 - x3.
constexpr double kCoef[3][5] = {{1, -1, 0, 0, 0}, {0, -1, 1, 0, 0}, {0, 0, 0, -1, 1}};

}  // namespace

SignedCurvature signed_curvature(const VecN<15>& x, double sigma_cm, bool weft, bool derivatives)
{
    SignedCurvature out;
    const Vec3 a0 = x.segment<3>(0) - x.segment<3>(3), b0 = x.segment<3>(6) - x.segment<3>(3), w0 = x.segment<3>(12) - x.segment<3>(9);
    const Vec3 n0 = weft ? Vec3((b0 - a0).cross(w0)) : Vec3(w0.cross(b0 - a0));
    const double A = a0.norm(), B = b0.norm(), Nn = n0.norm();
    if (!(A > 0) || !(B > 0) || !(Nn > 1e-12 * A * B * (1 + w0.norm() / std::max(A, B)))) return out;
    out.ok = true;
    // |a/|a| + b/|b|| = K sigma (Eq. 13's circle): q in 1/cm with sigma in cm.
    const double per_cm = 1.0 / sigma_cm;
    if (!derivatives) {
        out.q = (a0 / A + b0 / B).dot(n0 / Nn) * per_cm;
        return out;
    }
    V a, b, w;
    for (int i = 0; i < 3; ++i) {
        a[i].v = a0[i], a[i].g[i] = 1;
        b[i].v = b0[i], b[i].g[3 + i] = 1;
        w[i].v = w0[i], w[i].g[6 + i] = 1;
    }
    const V t = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const V n = weft ? cross(t, w) : cross(w, t);
    const V ah = scaled(a, inv_sqrt(dot(a, a))), bh = scaled(b, inv_sqrt(dot(b, b)));
    const V e = {ah[0] + bh[0], ah[1] + bh[1], ah[2] + bh[2]};
    const D q = per_cm * (dot(e, n) * inv_sqrt(dot(n, n)));
    out.q = q.v;
    for (int k = 0; k < 5; ++k) {
        Vec3 g = Vec3::Zero();
        for (int v = 0; v < 3; ++v) g += kCoef[v][k] * q.g.segment<3>(3 * v);
        out.gradient.segment<3>(3 * k) = g;
        for (int l = 0; l < 5; ++l) {
            Mat3 h = Mat3::Zero();
            for (int v = 0; v < 3; ++v)
                for (int u = 0; u < 3; ++u)
                    if (kCoef[v][k] != 0 && kCoef[u][l] != 0) h += kCoef[v][k] * kCoef[u][l] * q.h.block<3, 3>(3 * v, 3 * u);
            out.hessian.block<3, 3>(3 * k, 3 * l) = h;
        }
    }
    return out;
}

template <int N> MatN<N> psd_projection(const MatN<N>& H)
{
    Eigen::SelfAdjointEigenSolver<MatN<N>> es(0.5 * (H + H.transpose()));
    if (es.info() != Eigen::Success) return MatN<N>::Zero();
    if ((es.eigenvalues().array() >= 0).all()) return H;
    const VecN<N> clamped = es.eigenvalues().cwiseMax(0.0);
    return es.eigenvectors() * clamped.asDiagonal() * es.eigenvectors().transpose();
}
template MatN<6> psd_projection<6>(const MatN<6>&);
template MatN<12> psd_projection<12>(const MatN<12>&);
template MatN<15> psd_projection<15>(const MatN<15>&);

// ---------------------------------------------------------------------------------------------
// The terms

double SlipBendTerm::strain(const VecN<15>& x) const { return signed_curvature(x, sigma_cm_, weft_, false).q; }

Local<5> SlipBendTerm::evaluate(const VecN<15>& x, const SlipState& state, Derivatives what) const
{
    Local<5> l;
    const SignedCurvature sc = signed_curvature(x, sigma_cm_, weft_, what != Derivatives::NONE);
    if (!sc.ok) {
        l.vanishes = true;
        return l;
    }
    const Scalar3 f = law_.energy(sc.q, state);
    l.value = f.value;
    if (what == Derivatives::NONE) return l;
    l.gradient = f.d1 * sc.gradient;
    if (!wants_hessian(what)) return l;
    l.hessian = f.d2 * sc.gradient * sc.gradient.transpose() + f.d1 * sc.hessian;
    if (what == Derivatives::PROJECTED) l.hessian = psd_projection<15>(l.hessian);
    return l;
}

double SlipTrellisTerm::strain(const VecN<12>& x) const
{
    const Vec3 u = x.segment<3>(3) - x.head<3>(), v = x.tail<3>() - x.segment<3>(6);
    if (!(u.norm() > 0) || !(v.norm() > 0)) return 0;
    return -u.dot(v) / (u.norm() * v.norm());
}

Local<4> SlipTrellisTerm::evaluate(const VecN<12>& x, const SlipState& state, Derivatives what) const
{
    Local<4> l;
    const Vec3 u = x.segment<3>(3) - x.head<3>(), v = x.tail<3>() - x.segment<3>(6);
    if (!(u.norm() > 0) || !(v.norm() > 0)) {
        l.vanishes = true;
        return l;
    }
    const CosineDerivatives cd = cosine_between(u, v, wants_hessian(what));
    const Scalar3 f = law_.energy(-cd.c, state);  // q = -c
    l.value = f.value;
    if (what == Derivatives::NONE) return l;
    // dq = -dc, d2q = -d2c.
    l.gradient = to_particles<4>(kTrellisStencil, VecN<6>(-f.d1 * cd.gradient));
    if (!wants_hessian(what)) return l;
    MatN<6> H = f.d2 * cd.gradient * cd.gradient.transpose() - f.d1 * cd.hessian;
    if (what == Derivatives::PROJECTED) H = psd_projection<6>(H);
    l.hessian = to_particles<4>(kTrellisStencil, H);
    return l;
}

}  // namespace woven::model
