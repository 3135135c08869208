#pragma once
// Pictures of drapes: Embree ray casting of triangle meshes with Lambert shading and hard shadows.
#include <vector>

#include <Eigen/Core>

#include "woven/common/types.hpp"
#include "woven/geometry/triangle_mesh.hpp"
#include "woven/render/image.hpp"

namespace woven::render {

/// A pinhole camera (m): `fov_deg` is the vertical field of view in degrees.
struct Camera {
    Vec3 eye = Vec3(3, -3, 2);       ///< camera position (m)
    Vec3 target = Vec3::Zero();      ///< point looked at (m)
    Vec3 up = Vec3::UnitZ();         ///< approximate up direction (any vector not parallel to the view)
    double fov_deg = 35;             ///< vertical field of view (degrees)
};

/// A camera looking at the centre of the bounding box (lo, hi) from an elevated 3/4 view
/// (azimuth about +z from +x, elevation above the xy plane, both in degrees), +z up, at the
/// closest distance where all eight corners lie within 90 % of the vertical half field of view
/// both vertically and horizontally (so it frames the box for any image aspect >= 1).
Camera frame_box(const Vec3& lo, const Vec3& hi, double azimuth_deg = -35, double elevation_deg = 30);

/// One mesh to draw.
struct RenderMesh {
    geometry::TriangleMesh mesh;        ///< vertices (m) and faces
    Vec3 color{0.7, 0.7, 0.7};          ///< linear RGB albedo in 0..1
    /// Optional, one per vertex (else ignored); for cloth, (u, v) in thread counts along
    /// weft / warp, used for the woven-thread pattern.
    std::vector<Eigen::Vector2d> uv;
    /// Two-sided smooth shading plus a subtle plain-weave thread pattern from `uv` (faded out
    /// where threads are finer than a few pixels, so it never aliases).
    bool cloth = false;
};

/// Picture settings.
struct RenderOptions {
    int width = 1024;                                        ///< pixels, 1..16384
    int height = 768;                                        ///< pixels, 1..16384
    bool shadows = true;                                     ///< hard shadows from the light
    int samples_per_pixel = 4;                               ///< jittered, deterministic anti-aliasing
    Vec3 light_dir = Vec3(-0.4, -0.6, 1).normalized();       ///< direction towards the light
    Vec3 background{1, 1, 1};                                ///< linear RGB in 0..1
};

/// Ray-casts the meshes with Embree: Lambert + ambient + hard shadows from the directional
/// light, smooth normals (per-vertex normals from the faces; non-cloth meshes keep creases
/// sharper than 40 degrees, e.g. box edges), so a large ground plane mesh receives the
/// shadows of the others; gamma 2.2 output. Deterministic: the same input gives the same bytes.
/// Rows are shaded in parallel (OpenMP). Throws woven::InputError on bad options or a face
/// index out of range, woven::RuntimeError if Embree fails.
Image render(const std::vector<RenderMesh>& meshes, const Camera& camera, const RenderOptions& options = {});

}  // namespace woven::render
