#include "woven/geometry/primitives.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "woven/common/error.hpp"

namespace woven::geometry {
namespace {

void require_finite(const Vec3& v, const std::string& field)
{
    if (!v.allFinite()) throw InputError("", field, "finite numbers expected");
}

void require_positive(double x, const std::string& field)
{
    if (!std::isfinite(x) || !(x > 0)) throw InputError("", field, "a finite number > 0 expected");
}

Vec3 unit_direction(const Vec3& v, const std::string& field)
{
    require_finite(v, field);
    const double n = v.norm();
    if (!(n > 0)) throw InputError("", field, "a non-zero vector expected");
    return v / n;
}

/// Unit vectors u, v with (u, v, n) a right-handed orthonormal frame.
void complete_frame(const Vec3& n, Vec3& u, Vec3& v)
{
    const Vec3 helper = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    u = (helper - helper.dot(n) * n).normalized();
    v = n.cross(u);
}

/// Appends triangle (a, b, c), ordered counter-clockwise seen from outside a convex solid that
/// contains `inside`.
void add_triangle(TriangleMesh& m, int a, int b, int c, const Vec3& inside)
{
    const Vec3& A = m.vertices[a];
    const Vec3& B = m.vertices[b];
    const Vec3& C = m.vertices[c];
    const Vec3 n = (B - A).cross(C - A);
    if (n.dot((A + B + C) / 3.0 - inside) >= 0) {
        m.faces.emplace_back(a, b, c);
    } else {
        m.faces.emplace_back(a, c, b);
    }
}

/// Closed mesh of the convex hull of 8 corners indexed by bits (x: 1, y: 2, z: 4) of a
/// parallelepiped.
TriangleMesh hexahedron(const Vec3 corners[8])
{
    TriangleMesh m;
    Vec3 centre = Vec3::Zero();
    for (int i = 0; i < 8; ++i) {
        m.vertices.push_back(corners[i]);
        centre += corners[i] / 8.0;
    }
    // Each face: the 4 corners with one bit fixed, in cyclic order.
    for (int axis = 0; axis < 3; ++axis) {
        const int b1 = 1 << ((axis + 1) % 3), b2 = 1 << ((axis + 2) % 3);
        for (int side = 0; side < 2; ++side) {
            const int base = side ? (1 << axis) : 0;
            const int q[4] = {base, base | b1, base | b1 | b2, base | b2};
            add_triangle(m, q[0], q[1], q[2], centre);
            add_triangle(m, q[0], q[2], q[3], centre);
        }
    }
    return m;
}

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

// ---------------------------------------------------------------- Plane

Plane::Plane(const Vec3& point, const Vec3& normal, double render_size)
    : point_(point), normal_(unit_direction(normal, "normal")), render_size_(render_size)
{
    require_finite(point, "point");
    require_positive(render_size, "size");
}

double Plane::distance(const Vec3& p) const { return normal_.dot(p - point_); }

ClosestPoint Plane::closest(const Vec3& p) const
{
    const double d = distance(p);
    return {d, p - d * normal_, normal_};
}

std::optional<double> Plane::first_contact(const Vec3& p0, const Vec3& p1) const
{
    const double d0 = distance(p0);
    if (d0 <= 0) return 0.0;
    const double d1 = distance(p1);
    if (d1 > 0) return std::nullopt;
    return std::min(1.0, d0 / (d0 - d1));
}

TriangleMesh Plane::tessellate() const
{
    Vec3 u, v;
    complete_frame(normal_, u, v);
    const double h = 0.5 * render_size_, thickness = render_size_ / 100.0;
    Vec3 corners[8];
    for (int i = 0; i < 8; ++i) {
        corners[i] = point_ + ((i & 1) ? h : -h) * u + ((i & 2) ? h : -h) * v - ((i & 4) ? 0.0 : thickness) * normal_;
    }
    return hexahedron(corners);
}

Aabb Plane::bounds() const
{
    Aabb b;
    for (const Vec3& x : tessellate().vertices) b.extend(x);
    return b;
}

// ---------------------------------------------------------------- Box

Box::Box(const Vec3& centre, const Vec3& half_extents, double yaw)
    : centre_(centre), half_(half_extents), yaw_(yaw), c_(std::cos(yaw)), s_(std::sin(yaw))
{
    require_finite(centre, "centre");
    require_finite(half_extents, "half_extents");
    if (!(half_extents.minCoeff() > 0)) throw InputError("", "half_extents", "three numbers > 0 expected");
    if (!std::isfinite(yaw)) throw InputError("", "yaw", "a finite angle expected");
}

Vec3 Box::to_local(const Vec3& p) const
{
    const Vec3 w = p - centre_;
    return {c_ * w.x() + s_ * w.y(), -s_ * w.x() + c_ * w.y(), w.z()};
}

Vec3 Box::dir_to_world(const Vec3& v) const { return {c_ * v.x() - s_ * v.y(), s_ * v.x() + c_ * v.y(), v.z()}; }

Vec3 Box::to_world(const Vec3& q) const { return centre_ + dir_to_world(q); }

double Box::distance(const Vec3& p) const
{
    const Vec3 a = to_local(p).cwiseAbs() - half_;
    return a.cwiseMax(0.0).norm() + std::min(a.maxCoeff(), 0.0);
}

ClosestPoint Box::closest(const Vec3& p) const
{
    const Vec3 q = to_local(p);
    const Vec3 a = q.cwiseAbs() - half_;
    int i = 0;
    const double amax = a.maxCoeff(&i);
    if (amax > 0) {
        const Vec3 c = q.cwiseMax(-half_).cwiseMin(half_);
        const Vec3 diff = q - c;
        const double d = diff.norm();
        return {d, to_world(c), dir_to_world(diff / d)};
    }
    // Inside or on the surface: the nearest face is the one with the largest a_i.
    const double sign = q[i] >= 0 ? 1.0 : -1.0;
    Vec3 c = q;
    c[i] = sign * half_[i];
    Vec3 n = Vec3::Zero();
    n[i] = sign;
    return {amax, to_world(c), dir_to_world(n)};
}

std::optional<double> Box::first_contact(const Vec3& p0, const Vec3& p1) const
{
    const Vec3 q0 = to_local(p0);
    if ((q0.cwiseAbs() - half_).maxCoeff() <= 0) return 0.0;
    const Vec3 d = to_local(p1) - q0;
    double lo = 0, hi = 1;
    for (int k = 0; k < 3; ++k) {
        if (d[k] == 0) {
            if (std::abs(q0[k]) > half_[k]) return std::nullopt;
            continue;
        }
        double t1 = (-half_[k] - q0[k]) / d[k], t2 = (half_[k] - q0[k]) / d[k];
        if (t1 > t2) std::swap(t1, t2);
        lo = std::max(lo, t1);
        hi = std::min(hi, t2);
        if (lo > hi) return std::nullopt;
    }
    return lo;
}

Aabb Box::bounds() const
{
    const Vec3 e(std::abs(c_) * half_.x() + std::abs(s_) * half_.y(), std::abs(s_) * half_.x() + std::abs(c_) * half_.y(),
                 half_.z());
    return {centre_ - e, centre_ + e};
}

TriangleMesh Box::tessellate() const
{
    Vec3 corners[8];
    for (int i = 0; i < 8; ++i) {
        const Vec3 q((i & 1) ? half_.x() : -half_.x(), (i & 2) ? half_.y() : -half_.y(), (i & 4) ? half_.z() : -half_.z());
        corners[i] = to_world(q);
    }
    return hexahedron(corners);
}

// ---------------------------------------------------------------- Sphere

Sphere::Sphere(const Vec3& centre, double radius, int segments) : centre_(centre), radius_(radius), segments_(segments)
{
    require_finite(centre, "centre");
    require_positive(radius, "radius");
    if (segments < 8) throw InputError("", "segments", "an integer >= 8 expected");
}

double Sphere::distance(const Vec3& p) const { return (p - centre_).norm() - radius_; }

ClosestPoint Sphere::closest(const Vec3& p) const
{
    const Vec3 w = p - centre_;
    const double r = w.norm();
    const Vec3 n = r > 0 ? Vec3(w / r) : Vec3(Vec3::UnitZ());
    return {r - radius_, centre_ + radius_ * n, n};
}

std::optional<double> Sphere::first_contact(const Vec3& p0, const Vec3& p1) const
{
    const Vec3 m = p0 - centre_, d = p1 - p0;
    const double c = m.squaredNorm() - radius_ * radius_;
    if (c <= 0 || distance(p0) <= 0) return 0.0;
    const double a = d.squaredNorm(), b = m.dot(d);
    if (a == 0 || b >= 0) return std::nullopt;  // outside and not approaching the centre
    const double disc = b * b - a * c;
    if (disc < 0) return std::nullopt;
    const double t = c / (-b + std::sqrt(disc));  // smaller root, cancellation-free
    if (t > 1) return std::nullopt;
    return std::max(0.0, t);
}

Aabb Sphere::bounds() const { return {centre_ - Vec3::Constant(radius_), centre_ + Vec3::Constant(radius_)}; }

TriangleMesh Sphere::tessellate() const
{
    const int slices = segments_, stacks = std::max(4, segments_ / 2);
    TriangleMesh m;
    m.vertices.push_back(centre_ + radius_ * Vec3::UnitZ());
    for (int i = 1; i < stacks; ++i) {
        const double theta = std::numbers::pi * i / stacks;
        for (int j = 0; j < slices; ++j) {
            const double phi = 2.0 * std::numbers::pi * j / slices;
            m.vertices.push_back(centre_ + radius_ * Vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                                          std::cos(theta)));
        }
    }
    m.vertices.push_back(centre_ - radius_ * Vec3::UnitZ());
    const int south = static_cast<int>(m.vertices.size()) - 1;
    auto ring = [&](int i, int j) { return 1 + (i - 1) * slices + (j % slices); };
    for (int j = 0; j < slices; ++j) {
        add_triangle(m, 0, ring(1, j), ring(1, j + 1), centre_);
        add_triangle(m, south, ring(stacks - 1, j), ring(stacks - 1, j + 1), centre_);
        for (int i = 1; i + 1 < stacks; ++i) {
            add_triangle(m, ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), centre_);
            add_triangle(m, ring(i, j), ring(i + 1, j + 1), ring(i, j + 1), centre_);
        }
    }
    return m;
}

// ---------------------------------------------------------------- Cylinder

Cylinder::Cylinder(const Vec3& base_centre, double radius, double height, const Vec3& axis, int segments)
    : base_(base_centre), axis_(unit_direction(axis, "axis")), radius_(radius), height_(height), segments_(segments)
{
    require_finite(base_centre, "centre");
    require_positive(radius, "radius");
    require_positive(height, "height");
    if (segments < 8) throw InputError("", "segments", "an integer >= 8 expected");
    complete_frame(axis_, u_, v_);
}

double Cylinder::distance(const Vec3& p) const
{
    const Vec3 w = p - base_;
    const double s = w.dot(axis_);
    const double rho = (w - s * axis_).norm();
    const double dr = rho - radius_, dz = std::abs(s - 0.5 * height_) - 0.5 * height_;
    const double er = std::max(dr, 0.0), ez = std::max(dz, 0.0);
    return std::sqrt(er * er + ez * ez) + std::min(std::max(dr, dz), 0.0);
}

ClosestPoint Cylinder::closest(const Vec3& p) const
{
    const Vec3 w = p - base_;
    const double s = w.dot(axis_);
    const Vec3 radial = w - s * axis_;
    const double rho = radial.norm();
    const Vec3 er = rho > 0 ? Vec3(radial / rho) : u_;
    const double dr = rho - radius_, dz = std::abs(s - 0.5 * height_) - 0.5 * height_;
    if (dr > 0 || dz > 0) {
        const Vec3 c = base_ + std::clamp(s, 0.0, height_) * axis_ + std::min(rho, radius_) * er;
        const Vec3 diff = p - c;
        const double d = diff.norm();
        return {d, c, diff / d};
    }
    if (dr >= dz) return {dr, base_ + s * axis_ + radius_ * er, er};
    const bool top = s >= 0.5 * height_;
    return {dz, base_ + (top ? height_ : 0.0) * axis_ + radial, top ? axis_ : Vec3(-axis_)};
}

std::optional<double> Cylinder::first_contact(const Vec3& p0, const Vec3& p1) const
{
    if (distance(p0) <= 0) return 0.0;
    const Vec3 w0 = p0 - base_, D = p1 - p0;
    const double s0 = w0.dot(axis_), sd = D.dot(axis_);
    double lo = 0, hi = 1;
    // Between the caps: 0 <= s0 + t sd <= height.
    if (sd == 0) {
        if (s0 < 0 || s0 > height_) return std::nullopt;
    } else {
        double t1 = -s0 / sd, t2 = (height_ - s0) / sd;
        if (t1 > t2) std::swap(t1, t2);
        lo = std::max(lo, t1);
        hi = std::min(hi, t2);
        if (lo > hi) return std::nullopt;
    }
    // Inside the infinite cylinder: |r0 + t rd|^2 <= R^2, i.e. A t^2 + 2 B t + C <= 0.
    const Vec3 r0 = w0 - s0 * axis_, rd = D - sd * axis_;
    const double A = rd.squaredNorm(), B = r0.dot(rd), C = r0.squaredNorm() - radius_ * radius_;
    if (A == 0) {
        if (C > 0) return std::nullopt;
    } else {
        const double disc = B * B - A * C;
        if (disc < 0) return std::nullopt;
        const double q = -(B + std::copysign(std::sqrt(disc), B));
        double t1 = 0, t2 = 0;
        if (q != 0) {
            t1 = q / A;
            t2 = C / q;
        }
        if (t1 > t2) std::swap(t1, t2);
        lo = std::max(lo, t1);
        hi = std::min(hi, t2);
        if (lo > hi) return std::nullopt;
    }
    return lo;
}

Aabb Cylinder::bounds() const
{
    const Vec3 top = base_ + height_ * axis_;
    const Vec3 e = radius_ * (Vec3::Ones() - axis_.cwiseAbs2()).cwiseMax(0.0).cwiseSqrt();
    return {base_.cwiseMin(top) - e, base_.cwiseMax(top) + e};
}

TriangleMesh Cylinder::tessellate() const
{
    const int n = segments_;
    TriangleMesh m;
    const Vec3 top = base_ + height_ * axis_;
    const Vec3 inside = base_ + 0.5 * height_ * axis_;
    m.vertices.push_back(base_);
    m.vertices.push_back(top);
    for (int k = 0; k < 2; ++k) {
        for (int j = 0; j < n; ++j) {
            const double phi = 2.0 * std::numbers::pi * j / n;
            m.vertices.push_back((k ? top : base_) + radius_ * (std::cos(phi) * u_ + std::sin(phi) * v_));
        }
    }
    auto rim = [&](int k, int j) { return 2 + k * n + (j % n); };
    for (int j = 0; j < n; ++j) {
        add_triangle(m, 0, rim(0, j), rim(0, j + 1), inside);
        add_triangle(m, 1, rim(1, j), rim(1, j + 1), inside);
        add_triangle(m, rim(0, j), rim(0, j + 1), rim(1, j + 1), inside);
        add_triangle(m, rim(0, j), rim(1, j + 1), rim(1, j), inside);
    }
    return m;
}

}  // namespace woven::geometry
