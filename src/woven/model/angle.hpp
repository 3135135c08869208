#pragma once
// The angle the bending and trellis terms depend on (terms.hpp), with its derivatives:
//
//   c = cos(angle between a and b) = a.b/(|a||b|)  with a, b affine in the particles:
//     bending  (3 particles, x1 the middle):   a = x0 - x1,  b = x2 - x1      theta = acos(c)
//
//            x0 ---- x1 ---- x2         (one thread line)
//
//     trellis  (4 particles around k):  u = xR - xL,  v = xU - xD,   phi = -asin(c)
//
//                    xU
//                     |
//              xL --- k --- xR          (phi does not depend on k itself)
//                     |
//                    xD
#include <array>

#include "woven/common/types.hpp"

namespace woven::model {

/// c = a.b/(|a||b|), its gradient with respect to (a, b) and Hessian (6 by 6, blocks aa ab ba bb).
struct CosineDerivatives {
    double c = 0;
    VecN<6> gradient = VecN<6>::Zero();
    MatN<6> hessian = MatN<6>::Zero();
};
CosineDerivatives cosine_between(const Vec3& a, const Vec3& b, bool want_hessian);

/// Gauss-Newton replacement of the Hessian of c for bending: J^T J with J = d(a/|a| + b/|b|)/d(a,b).
/// PSD, and equal to the Hessian of c at a straight thread (theta = pi), where c's own Hessian
/// is what matters for bending stiffness.
MatN<6> bending_gauss_newton(const Vec3& a, const Vec3& b);

/// Coefficients of the particles of an N-particle stencil in the vectors a and b
/// (a = sum alpha_k x_k, b = sum beta_k x_k).
template <int N> struct AffinePair {
    std::array<double, N> alpha;
    std::array<double, N> beta;
};
inline constexpr AffinePair<3> kBendingStencil{{1, -1, 0}, {0, -1, 1}};
inline constexpr AffinePair<4> kTrellisStencil{{-1, 1, 0, 0}, {0, 0, -1, 1}};  // order L R D U

/// Maps a gradient in (a, b) to the N particles of the stencil.
template <int N> VecN<3 * N> to_particles(const AffinePair<N>& s, const VecN<6>& g)
{
    VecN<3 * N> out;
    for (int k = 0; k < N; ++k) out.template segment<3>(3 * k) = s.alpha[k] * g.head<3>() + s.beta[k] * g.tail<3>();
    return out;
}

/// Maps a Hessian in (a, b) to the N particles of the stencil.
template <int N> MatN<3 * N> to_particles(const AffinePair<N>& s, const MatN<6>& H)
{
    MatN<3 * N> out;
    for (int k = 0; k < N; ++k)
        for (int l = 0; l < N; ++l)
            out.template block<3, 3>(3 * k, 3 * l) = s.alpha[k] * s.alpha[l] * H.topLeftCorner<3, 3>()
                + s.alpha[k] * s.beta[l] * H.topRightCorner<3, 3>() + s.beta[k] * s.alpha[l] * H.bottomLeftCorner<3, 3>()
                + s.beta[k] * s.beta[l] * H.bottomRightCorner<3, 3>();
    return out;
}

/// Particle k's part of to_particles(s, g): alpha_k g_a + beta_k g_b.
template <int N> Vec3 to_particle(const AffinePair<N>& s, const VecN<6>& g, int k)
{
    return s.alpha[k] * g.head<3>() + s.beta[k] * g.tail<3>();
}

/// Particle k's diagonal 3x3 block of to_particles(s, H).
template <int N> Mat3 to_particle_block(const AffinePair<N>& s, const MatN<6>& H, int k)
{
    return s.alpha[k] * s.alpha[k] * H.topLeftCorner<3, 3>() + s.alpha[k] * s.beta[k] * H.topRightCorner<3, 3>()
        + s.beta[k] * s.alpha[k] * H.bottomLeftCorner<3, 3>() + s.beta[k] * s.beta[k] * H.bottomRightCorner<3, 3>();
}

}  // namespace woven::model
