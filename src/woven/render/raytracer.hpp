#pragma once
// Pictures of drapes: Embree ray casting of triangle meshes. A key light with soft shadows
// (an area light of small angular radius), a sky term with ambient occlusion, smooth
// (interpolated vertex-normal) shading, stratified anti-aliasing; the cloth is drawn over any
// obstacle it lies on (see RenderOptions::cloth_priority_m).
//
// What Embree does: the BVH and every ray query (primary, shadow, occlusion). What is written
// here by hand: the camera, sampling, the shading model and the cloth's thread pattern -- a
// few hundred lines that a path tracer (e.g. Mitsuba, Cycles) would replace with far more
// machinery than a Debian package offers for a headless 2-core build.
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "woven/common/types.hpp"
#include "woven/geometry/triangle_mesh.hpp"
#include "woven/render/image.hpp"

namespace woven::render {

/// A pinhole camera (m): `fov_deg` is the vertical field of view in degrees.
struct Camera {
    Vec3 eye = Vec3(3, -3, 2);   ///< camera position (m)
    Vec3 target = Vec3::Zero();  ///< point looked at (m)
    Vec3 up = Vec3::UnitZ();     ///< approximate up direction (any vector not parallel to the view)
    double fov_deg = 35;         ///< vertical field of view (degrees)
};

/// A camera looking at the centre of the bounding box (lo, hi) from an elevated 3/4 view
/// (azimuth about +z from +x, elevation above the xy plane, both in degrees), +z up, at the
/// closest distance where all eight corners lie within 90 % of the vertical half field of view
/// both vertically and horizontally (so it frames the box for any image aspect >= 1).
Camera frame_box(const Vec3& lo, const Vec3& hi, double azimuth_deg = -35, double elevation_deg = 30);

/// The tightest camera looking along `forward` (any non-zero vector) with vertical field of view
/// fov_deg and width/height `aspect` that sees every point within `fill` (0..1] of the half
/// field of view, horizontally and vertically: the eye is placed exactly (the frame touches the
/// outermost points after the margin). `up` as in Camera. Points that are not finite are
/// ignored; with none left the camera looks at the origin from 1 m.
Camera fit_camera(const std::vector<Vec3>& points, const Vec3& forward, const Vec3& up, double fov_deg, double aspect, double fill = 0.92);

/// What a mesh is made of.
enum class Surface {
    SOLID,  ///< an obstacle: neutral matte
    CLOTH,  ///< two-sided, thread pattern from `uv`, drawn over solids it lies on
    FLOOR,  ///< matte, fades into the background far from the other meshes
};

/// One mesh to draw.
struct RenderMesh {
    geometry::TriangleMesh mesh;  ///< vertices (m) and faces
    Vec3 color{0.7, 0.7, 0.7};    ///< linear RGB albedo in 0..1
    /// Optional, one per vertex (else ignored); for cloth, (u, v) in thread counts along
    /// weft / warp (one unit per particle spacing), used for the thread pattern.
    std::vector<Eigen::Vector2d> uv;
    Surface surface = Surface::SOLID;  ///< material
    /// Optional, one unit normal per vertex (else from the faces: area-weighted, solids and
    /// floors keep creases sharper than 40 degrees, e.g. box edges).
    std::vector<Vec3> normals;
};

/// Picture settings.
struct RenderOptions {
    int width = 1024;                                     ///< pixels, 1..16384
    int height = 768;                                     ///< pixels, 1..16384
    int samples_per_pixel = 16;                           ///< stratified, deterministic (rounded up to a square)
    bool shadows = true;                                  ///< shadows from the key light
    double light_radius_deg = 4;                          ///< angular radius of the key light (0: hard shadows)
    Vec3 light_dir = Vec3(-0.45, -0.75, 1).normalized();  ///< direction towards the key light
    double light = 1.05;                                  ///< key light irradiance (linear, 0..)
    double sky = 0.32;                                    ///< sky (ambient) light (linear, 0..)
    bool ambient_occlusion = true;                        ///< occlude the sky term
    double ao_distance_m = 0;                             ///< AO ray length (m); 0: 0.2 x the radius of the non-floor meshes
    /// A cloth surface behind an obstacle surface by less than this along a ray (m) is drawn in
    /// front of it, and the obstacle does not shadow the cloth within it: a cloth lying on an
    /// obstacle is flat between its particles, so the obstacle's edges poke through it by up to
    /// half the particle spacing. Where such a poke reaches past the cloth's silhouette, an
    /// obstacle point (not the floor) closer to the cloth than this distance shows the
    /// cloth. 0: the longest cloth edge; negative: off.
    double cloth_priority_m = 0;
    double pattern = 1;        ///< strength of the cloth's thread pattern (0: plain)
    Vec3 background{1, 1, 1};  ///< linear RGB in 0..1
    /// Called now and then with the fraction of rows shaded (0..1), from one thread at a time;
    /// may be empty.
    std::function<void(double)> progress;
};

/// Ray-casts the meshes with Embree (see the file comment), gamma 2.2 output. Deterministic:
/// the same input gives the same bytes, whatever the thread count (rows are shaded in
/// parallel, OpenMP). Throws woven::InputError on bad options, a face index out of range or a
/// normals/uv array of the wrong size, woven::RuntimeError if Embree fails. Faces with a
/// non-finite vertex are skipped.
Image render(const std::vector<RenderMesh>& meshes, const Camera& camera, const RenderOptions& options = {});

}  // namespace woven::render
