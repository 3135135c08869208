#pragma once
// Analytic obstacles with exact signed distance fields: half-space, box, sphere, capped cylinder.
// All lengths in m, angles in rad. Constructors throw woven::InputError("", field, expected)
// on bad input (the scene loader fills in the source).
#include "woven/geometry/obstacle.hpp"

namespace woven::geometry {

/// Half-space: solid below the plane through `point` with outward `normal`. The distance is
/// n . (p - point). For rendering it is a square of side `render_size` centred on `point`
/// (tessellated as a thin closed slab of thickness render_size / 100 under the plane).
class Plane : public Obstacle {
public:
    /// normal: any non-zero finite vector (normalised here); render_size > 0 (m).
    Plane(const Vec3& point, const Vec3& normal, double render_size = 6.0);
    ClosestPoint closest(const Vec3& p) const override;
    double distance(const Vec3& p) const override;
    /// Analytic: the linear distance crosses 0 at most once.
    std::optional<double> first_contact(const Vec3& p0, const Vec3& p1) const override;
    /// Bounds of the rendered slab (the half-space itself is unbounded).
    Aabb bounds() const override;
    TriangleMesh tessellate() const override;
    std::string kind() const override { return "plane"; }

    /// A point on the plane (m).
    const Vec3& point() const { return point_; }
    /// Outward unit normal.
    const Vec3& normal() const { return normal_; }
    /// Side of the rendered square (m).
    double render_size() const { return render_size_; }

private:
    Vec3 point_, normal_;
    double render_size_;
};

/// Solid box: centre, half extents along its local axes, rotated by `yaw` (rad) about +z.
/// Exact Euclidean signed distance inside and outside.
class Box : public Obstacle {
public:
    /// half_extents: all > 0 (m); yaw finite (rad).
    Box(const Vec3& centre, const Vec3& half_extents, double yaw = 0.0);
    ClosestPoint closest(const Vec3& p) const override;
    double distance(const Vec3& p) const override;
    /// Analytic slab test in the box frame.
    std::optional<double> first_contact(const Vec3& p0, const Vec3& p1) const override;
    Aabb bounds() const override;
    /// 12 triangles.
    TriangleMesh tessellate() const override;
    std::string kind() const override { return "box"; }

    /// Centre (m).
    const Vec3& centre() const { return centre_; }
    /// Half extents along the box axes (m).
    const Vec3& half_extents() const { return half_; }
    /// Rotation about +z (rad).
    double yaw() const { return yaw_; }

private:
    Vec3 to_local(const Vec3& p) const;    // world point -> box frame
    Vec3 to_world(const Vec3& q) const;    // box frame point -> world
    Vec3 dir_to_world(const Vec3& v) const;
    Vec3 centre_, half_;
    double yaw_, c_, s_;
};

/// Solid sphere.
class Sphere : public Obstacle {
public:
    /// radius > 0 (m); segments >= 8: slices of the rendering mesh (half as many stacks).
    Sphere(const Vec3& centre, double radius, int segments = 48);
    ClosestPoint closest(const Vec3& p) const override;
    double distance(const Vec3& p) const override;
    /// Analytic segment/sphere intersection.
    std::optional<double> first_contact(const Vec3& p0, const Vec3& p1) const override;
    Aabb bounds() const override;
    /// UV sphere with its vertices on the surface.
    TriangleMesh tessellate() const override;
    std::string kind() const override { return "sphere"; }

    /// Centre (m).
    const Vec3& centre() const { return centre_; }
    /// Radius (m).
    double radius() const { return radius_; }

private:
    Vec3 centre_;
    double radius_;
    int segments_;
};

/// Solid capped cylinder from base_centre to base_centre + height * axis; a drape-tester disc
/// is a short one (e.g. 3 mm). Exact signed distance (including the rims).
class Cylinder : public Obstacle {
public:
    /// radius > 0, height > 0 (m); axis: non-zero (normalised here); segments >= 8 around the rim
    /// for rendering.
    Cylinder(const Vec3& base_centre, double radius, double height, const Vec3& axis = Vec3::UnitZ(),
             int segments = 64);
    ClosestPoint closest(const Vec3& p) const override;
    double distance(const Vec3& p) const override;
    /// Analytic: infinite-cylinder quadratic intersected with the slab between the caps.
    std::optional<double> first_contact(const Vec3& p0, const Vec3& p1) const override;
    Aabb bounds() const override;
    /// Prism with `segments` sides, rim vertices on the surface, fan-triangulated caps.
    TriangleMesh tessellate() const override;
    std::string kind() const override { return "cylinder"; }

    /// Centre of the base cap (m).
    const Vec3& base_centre() const { return base_; }
    /// Unit axis from the base cap to the top cap.
    const Vec3& axis() const { return axis_; }
    /// Radius (m).
    double radius() const { return radius_; }
    /// Height (m).
    double height() const { return height_; }

private:
    Vec3 base_, axis_, u_, v_;  // u_, v_: unit vectors completing axis_ to an orthonormal frame
    double radius_, height_;
    int segments_;
};

}  // namespace woven::geometry
