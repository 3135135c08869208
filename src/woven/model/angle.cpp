#include "woven/model/angle.hpp"

namespace woven::model {

CosineDerivatives cosine_between(const Vec3& a, const Vec3& b, bool want_hessian)
{
    CosineDerivatives d;
    const double A = a.norm(), B = b.norm();
    const Vec3 ah = a / A, bh = b / B;
    d.c = ah.dot(bh);
    const Vec3 ga = (bh - d.c * ah) / A;  // dc/da
    const Vec3 gb = (ah - d.c * bh) / B;  // dc/db
    d.gradient << ga, gb;
    if (!want_hessian) return d;
    const Mat3 I = Mat3::Identity();
    const Mat3 Pa = (I - ah * ah.transpose()) / A;  // d(a/|a|)/da
    const Mat3 Pb = (I - bh * bh.transpose()) / B;
    d.hessian.topLeftCorner<3, 3>() = -(ga * ah.transpose() + ah * ga.transpose()) / A - d.c * Pa / A;
    d.hessian.bottomRightCorner<3, 3>() = -(gb * bh.transpose() + bh * gb.transpose()) / B - d.c * Pb / B;
    const Mat3 Hab = (Pb - ah * gb.transpose()) / A;
    d.hessian.topRightCorner<3, 3>() = Hab;
    d.hessian.bottomLeftCorner<3, 3>() = Hab.transpose();
    return d;
}

MatN<6> bending_gauss_newton(const Vec3& a, const Vec3& b)
{
    const double A = a.norm(), B = b.norm();
    const Vec3 ah = a / A, bh = b / B;
    const Mat3 I = Mat3::Identity();
    const Mat3 Pa = (I - ah * ah.transpose()) / A;
    const Mat3 Pb = (I - bh * bh.transpose()) / B;
    MatN<6> H;
    H.topLeftCorner<3, 3>() = Pa * Pa;
    H.topRightCorner<3, 3>() = Pa * Pb;
    H.bottomLeftCorner<3, 3>() = Pb * Pa;
    H.bottomRightCorner<3, 3>() = Pb * Pb;
    return H;
}

}  // namespace woven::model
