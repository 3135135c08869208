#include "woven/render/raytracer.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numbers>
#include <numeric>
#include <string>

#include <Eigen/Geometry>
#include <embree3/rtcore.h>

#include "woven/common/error.hpp"
#include "woven/geometry/mesh_obstacle.hpp"

namespace woven::render {

namespace {

constexpr double kCreaseDeg = 40;        // solids: faces meeting sharper than this keep a crease
constexpr double kFloorFadeStart = 1.6;  // floor fades into the background from this many subject radii...
constexpr double kFloorFadeEnd = 4.0;    // ... to this many
constexpr double kClothBackShade = 0.8;  // the back (inside) of the cloth is this much darker
constexpr double kWarpLine = 0.22;       // darkening on a warp thread line (constant u)
constexpr double kWeftLine = 0.12;       // darkening on a weft thread line (constant v)
constexpr double kLineWidth = 0.14;      // thread line width, in particle spacings

Vec3 any_perpendicular(const Vec3& v)
{
    const Vec3 a = std::abs(v.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    return v.cross(a).normalized();
}

/// An orthonormal frame (t, b, n) around the unit vector n.
void frame_around(const Vec3& n, Vec3& t, Vec3& b)
{
    t = any_perpendicular(n);
    b = n.cross(t);
}

/// Mesh data prepared for shading; faces with non-finite vertices are dropped.
struct Prepared {
    const RenderMesh* source = nullptr;
    std::vector<int> faces;                           // Embree primID -> face index
    std::vector<Vec3> face_normals;                   // per kept face (unit, zero if degenerate)
    std::vector<std::array<Vec3, 3>> corner_normals;  // per kept face
    bool has_uv = false;
    double threads_per_metre = 0;  // uv length per world length
    double longest_edge = 0;       // m
};

Prepared prepare(const RenderMesh& rm, std::size_t index)
{
    Prepared p;
    p.source = &rm;
    const auto& V = rm.mesh.vertices;
    const auto& F = rm.mesh.faces;
    const int nv = static_cast<int>(V.size());
    const std::string name = "mesh " + std::to_string(index);
    if (!rm.uv.empty() && rm.uv.size() != V.size()) throw InputError("render", name, "one uv per vertex, or none");
    if (!rm.normals.empty() && rm.normals.size() != V.size()) throw InputError("render", name, "one normal per vertex, or none");
    std::vector<Vec3> area_normals;  // unnormalised, |n| = 2 * area
    for (std::size_t f = 0; f < F.size(); ++f) {
        const Eigen::Vector3i& t = F[f];
        for (int k = 0; k < 3; ++k)
            if (t[k] < 0 || t[k] >= nv) throw InputError("render", name, "face " + std::to_string(f) + " has a vertex index out of range");
        if (!V[t[0]].allFinite() || !V[t[1]].allFinite() || !V[t[2]].allFinite()) continue;
        p.faces.push_back(static_cast<int>(f));
        const Vec3 n = (V[t[1]] - V[t[0]]).cross(V[t[2]] - V[t[0]]);
        area_normals.push_back(n);
        const double len = n.norm();
        p.face_normals.push_back(len > 0 ? Vec3(n / len) : Vec3::Zero());
        for (int k = 0; k < 3; ++k) p.longest_edge = std::max(p.longest_edge, (V[t[k]] - V[t[(k + 1) % 3]]).norm());
    }

    p.corner_normals.resize(p.faces.size());
    if (!rm.normals.empty()) {
        for (std::size_t j = 0; j < p.faces.size(); ++j)
            for (int k = 0; k < 3; ++k) {
                const Vec3& n = rm.normals[F[p.faces[j]][k]];
                p.corner_normals[j][k] = n.allFinite() && n.norm() > 1e-12 ? Vec3(n.normalized()) : p.face_normals[j];
            }
    } else {
        // Vertex -> adjacent kept faces.
        std::vector<int> offsets(nv + 1, 0);
        for (int pf : p.faces)
            for (int k = 0; k < 3; ++k) ++offsets[F[pf][k] + 1];
        for (int i = 0; i < nv; ++i) offsets[i + 1] += offsets[i];
        std::vector<int> adjacent(offsets[nv]);
        {
            std::vector<int> fill(offsets.begin(), offsets.end() - 1);
            for (std::size_t j = 0; j < p.faces.size(); ++j)
                for (int k = 0; k < 3; ++k) adjacent[fill[F[p.faces[j]][k]]++] = static_cast<int>(j);
        }
        const double crease_cos = rm.surface == Surface::CLOTH ? -2.0 : std::cos(kCreaseDeg * std::numbers::pi / 180.0);
        for (std::size_t j = 0; j < p.faces.size(); ++j) {
            const Vec3& fn = p.face_normals[j];
            for (int k = 0; k < 3; ++k) {
                const int v = F[p.faces[j]][k];
                Vec3 sum = Vec3::Zero();
                for (int a = offsets[v]; a < offsets[v + 1]; ++a) {
                    const int g = adjacent[a];
                    if (p.face_normals[g].dot(fn) > crease_cos) sum += area_normals[g];
                }
                const double len = sum.norm();
                p.corner_normals[j][k] = len > 1e-300 ? Vec3(sum / len) : fn;
            }
        }
    }

    p.has_uv = !rm.uv.empty() && !V.empty();
    if (p.has_uv) {
        double uv_len = 0, world_len = 0;
        for (int pf : p.faces)
            for (int k = 0; k < 3; ++k) {
                const int a = F[pf][k], b = F[pf][(k + 1) % 3];
                const double du = (rm.uv[a] - rm.uv[b]).norm();
                if (!std::isfinite(du)) continue;
                uv_len += du;
                world_len += (V[a] - V[b]).norm();
            }
        p.threads_per_metre = world_len > 0 ? uv_len / world_len : 0;
    }
    return p;
}

/// Fraction of [x - w/2, x + w/2] within kLineWidth / 2 of an integer (a box-filtered line
/// pattern, so thread lines never alias); w in the same units as x.
double line_coverage(double x, double w)
{
    const double h = 0.5 * kLineWidth;
    auto integral = [h](double t) {  // integral of the line indicator from 0 to t
        const double s = t + h;
        const double fl = std::floor(s);
        return fl * kLineWidth + std::min(s - fl, kLineWidth) - h;
    };
    if (w < 1e-6) {
        const double f = x - std::floor(x + 0.5);
        return std::abs(f) <= h ? 1.0 : 0.0;
    }
    return std::clamp((integral(x + 0.5 * w) - integral(x - 0.5 * w)) / w, 0.0, 1.0);
}

std::uint32_t hash32(std::uint32_t x)
{
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}

/// A deterministic number in [0, 1) for pixel (px, py) and a stream.
double hash01(int px, int py, std::uint32_t stream)
{
    std::uint32_t h = hash32(static_cast<std::uint32_t>(px) * 0x9E3779B1U ^ hash32(static_cast<std::uint32_t>(py) + 0x85EBCA77U));
    h = hash32(h ^ (stream * 0xC2B2AE3DU + 0x27D4EB2FU));
    return (h >> 8) * (1.0 / 16777216.0);
}

struct DeviceDeleter {
    void operator()(RTCDevice d) const { rtcReleaseDevice(d); }
};
struct SceneDeleter {
    void operator()(RTCScene s) const { rtcReleaseScene(s); }
};
using DeviceHandle = std::unique_ptr<std::remove_pointer_t<RTCDevice>, DeviceDeleter>;
using SceneHandle = std::unique_ptr<std::remove_pointer_t<RTCScene>, SceneDeleter>;

void check(RTCDevice device, const char* what)
{
    const RTCError e = rtcGetDeviceError(device);
    if (e != RTC_ERROR_NONE) throw RuntimeError(std::string("render: Embree error ") + std::to_string(static_cast<int>(e)) + " in " + what);
}

std::uint8_t to_srgb8(double linear)
{
    const double c = std::clamp(linear, 0.0, 1.0);
    return static_cast<std::uint8_t>(std::lround(255.0 * std::pow(c, 1.0 / 2.2)));
}

/// The three Embree scenes: everything (camera rays), the cloth alone and the rest.
struct Scenes {
    SceneHandle all, cloth, solid;
    std::vector<int> all_to_mesh, cloth_to_mesh;  // geometry id -> mesh index
};

void attach(RTCDevice device, RTCScene scene, const RenderMesh& rm, const Prepared& p, std::vector<int>& to_mesh, int mesh)
{
    const auto& V = rm.mesh.vertices;
    const auto& F = rm.mesh.faces;
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb =
        static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), V.size()));
    auto* ib = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), p.faces.size()));
    check(device, "rtcSetNewGeometryBuffer");
    for (std::size_t v = 0; v < V.size(); ++v)
        for (int k = 0; k < 3; ++k) vb[3 * v + k] = std::isfinite(V[v][k]) ? static_cast<float>(V[v][k]) : 0.0f;
    for (std::size_t j = 0; j < p.faces.size(); ++j)
        for (int k = 0; k < 3; ++k) ib[3 * j + k] = static_cast<unsigned>(F[p.faces[j]][k]);
    rtcCommitGeometry(geom);
    const unsigned id = rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    if (to_mesh.size() <= id) to_mesh.resize(id + 1, -1);
    to_mesh[id] = mesh;
}

struct Hit {
    bool found = false;
    int mesh = -1;
    int prim = -1;
    double t = 0, u = 0, v = 0;
};

Hit intersect(RTCScene scene, const std::vector<int>& to_mesh, const Vec3& org, const Vec3& dir, double tfar)
{
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    rh.ray.org_x = static_cast<float>(org.x());
    rh.ray.org_y = static_cast<float>(org.y());
    rh.ray.org_z = static_cast<float>(org.z());
    rh.ray.dir_x = static_cast<float>(dir.x());
    rh.ray.dir_y = static_cast<float>(dir.y());
    rh.ray.dir_z = static_cast<float>(dir.z());
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = static_cast<float>(tfar);
    rh.ray.time = 0.0f;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &ctx, &rh);
    Hit h;
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
    h.found = true;
    h.mesh = to_mesh[rh.hit.geomID];
    h.prim = static_cast<int>(rh.hit.primID);
    h.t = rh.ray.tfar;
    h.u = rh.hit.u;
    h.v = rh.hit.v;
    return h;
}

bool occluded(RTCScene scene, const Vec3& org, const Vec3& dir, double tnear, double tfar)
{
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay ray;
    ray.org_x = static_cast<float>(org.x());
    ray.org_y = static_cast<float>(org.y());
    ray.org_z = static_cast<float>(org.z());
    ray.dir_x = static_cast<float>(dir.x());
    ray.dir_y = static_cast<float>(dir.y());
    ray.dir_z = static_cast<float>(dir.z());
    ray.tnear = static_cast<float>(tnear);
    ray.tfar = static_cast<float>(tfar);
    ray.time = 0.0f;
    ray.mask = 0xFFFFFFFFu;
    ray.id = 0;
    ray.flags = 0;
    rtcOccluded1(scene, &ctx, &ray);
    return ray.tfar < 0;
}

}  // namespace

Camera frame_box(const Vec3& lo, const Vec3& hi, double azimuth_deg, double elevation_deg)
{
    Camera cam;
    Vec3 centre = 0.5 * (lo + hi);
    double radius = 0.5 * (hi - lo).norm();
    if (!centre.allFinite() || !std::isfinite(radius)) {
        centre = Vec3::Zero();
        radius = 1;
    }
    if (radius <= 0) radius = 1;
    const double az = azimuth_deg * std::numbers::pi / 180.0, el = elevation_deg * std::numbers::pi / 180.0;
    const Vec3 dir(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    const double half_fov = 0.5 * cam.fov_deg * std::numbers::pi / 180.0;
    const double limit = 0.9 * std::tan(half_fov);  // keep the box within 90 % of the half height
    // Grow from the bounding-sphere distance until the box fits, then bisect for the closest
    // distance at which the eight corners fit both vertically and horizontally.
    const Vec3 forward = -dir;
    Vec3 right = forward.cross(Vec3::UnitZ());
    right = right.norm() > 1e-9 ? Vec3(right.normalized()) : any_perpendicular(forward);
    const Vec3 up = right.cross(forward);
    auto fits = [&](double d) {
        const Vec3 eye = centre + d * dir;
        for (int i = 0; i < 8; ++i) {
            const Vec3 corner((i & 1) ? hi.x() : lo.x(), (i & 2) ? hi.y() : lo.y(), (i & 4) ? hi.z() : lo.z());
            const Vec3 q = (corner.allFinite() ? corner : centre) - eye;
            const double depth = q.dot(forward);
            if (depth <= 0) return false;
            if (std::abs(q.dot(up)) > limit * depth || std::abs(q.dot(right)) > limit * depth) return false;
        }
        return true;
    };
    double d_near = 0, d_far = radius / std::sin(half_fov);
    for (int it = 0; it < 60 && !fits(d_far); ++it) d_far *= 2;
    for (int it = 0; it < 50; ++it) {
        const double mid = 0.5 * (d_near + d_far);
        (fits(mid) ? d_far : d_near) = mid;
    }
    cam.target = centre;
    cam.eye = centre + d_far * dir;
    cam.up = Vec3::UnitZ();
    return cam;
}

Camera fit_camera(const std::vector<Vec3>& points, const Vec3& forward_in, const Vec3& up_in, double fov_deg, double aspect, double fill)
{
    Camera cam;
    cam.fov_deg = fov_deg;
    cam.up = up_in;
    const Vec3 f = forward_in.norm() > 0 ? Vec3(forward_in.normalized()) : Vec3(-Vec3::UnitZ());
    Vec3 r = f.cross(up_in);
    r = r.norm() > 1e-9 ? Vec3(r.normalized()) : any_perpendicular(f);
    const Vec3 u = r.cross(f);
    std::vector<Vec3> q;  // (right, up, forward) coordinates
    for (const Vec3& p : points)
        if (p.allFinite()) q.emplace_back(p.dot(r), p.dot(u), p.dot(f));
    if (q.empty()) {
        cam.target = Vec3::Zero();
        cam.eye = -f;
        return cam;
    }
    const double ty = fill * std::tan(0.5 * fov_deg * std::numbers::pi / 180.0), tx = ty * aspect;
    // With the eye at a r + b u + e f, a point is inside when |x - a| <= tx (z - e) (and the
    // same vertically): the farthest-forward eye is e = min_p (z - |x - a| / tx), a concave
    // function of a; a ternary search finds its best a (and b for the vertical).
    auto best = [&](int axis, double tan_half, double& centre) {
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (const Vec3& c : q) {
            lo = std::min(lo, c[axis]);
            hi = std::max(hi, c[axis]);
        }
        auto e_of = [&](double a) {
            double e = std::numeric_limits<double>::infinity();
            for (const Vec3& c : q) e = std::min(e, c.z() - std::abs(c[axis] - a) / tan_half);
            return e;
        };
        for (int it = 0; it < 100; ++it) {
            const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
            (e_of(m1) < e_of(m2) ? lo : hi) = (e_of(m1) < e_of(m2) ? m1 : m2);
        }
        centre = 0.5 * (lo + hi);
        return e_of(centre);
    };
    double a = 0, b = 0;
    const double ex = best(0, tx, a), ey = best(1, ty, b);
    double e = std::min(ex, ey);
    double zmin = std::numeric_limits<double>::infinity();
    for (const Vec3& c : q) zmin = std::min(zmin, c.z());
    if (!(e < zmin)) e = zmin - 1;  // a single point or a flat set seen edge-on
    cam.eye = a * r + b * u + e * f;
    cam.target = cam.eye + f;
    return cam;
}

Image render(const std::vector<RenderMesh>& meshes, const Camera& camera, const RenderOptions& options)
{
    const int W = options.width, H = options.height;
    if (W < 1 || W > 16384 || H < 1 || H > 16384) throw InputError("render", "size", "width and height in 1..16384 pixels");
    if (!(camera.fov_deg > 0 && camera.fov_deg < 179)) throw InputError("render", "camera.fov_deg", "a field of view in (0, 179) degrees");
    const Vec3 forward_raw = camera.target - camera.eye;
    if (!camera.eye.allFinite() || !forward_raw.allFinite() || forward_raw.norm() <= 0)
        throw InputError("render", "camera", "finite eye and target at distinct points");
    if (!options.light_dir.allFinite() || options.light_dir.norm() <= 0)
        throw InputError("render", "light_dir", "a finite non-zero direction");
    if (!(options.light_radius_deg >= 0 && options.light_radius_deg < 90))
        throw InputError("render", "light_radius_deg", "an angle in [0, 90) degrees");
    if (!std::isfinite(options.cloth_priority_m) || !(options.ao_distance_m >= 0) || !std::isfinite(options.ao_distance_m))
        throw InputError("render", "cloth_priority_m, ao_distance_m", "finite lengths (ao_distance_m >= 0)");
    const int grid = std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(std::max(1, options.samples_per_pixel))))));
    const int spp = grid * grid;
    const Vec3 light = options.light_dir.normalized();
    Vec3 light_t, light_b;
    frame_around(light, light_t, light_b);
    const double cos_light = std::cos(options.light_radius_deg * std::numbers::pi / 180.0);

    // Camera basis.
    const Vec3 forward = forward_raw.normalized();
    Vec3 right = forward.cross(camera.up);
    right = right.norm() > 1e-9 * std::max(1.0, camera.up.norm()) ? Vec3(right.normalized()) : any_perpendicular(forward);
    const Vec3 up = right.cross(forward);
    const double tan_half = std::tan(0.5 * camera.fov_deg * std::numbers::pi / 180.0);
    const double aspect = static_cast<double>(W) / H;
    const double pixel_angle = 2 * tan_half / H;  // world size of a pixel at unit distance

    // Prepare meshes, their bounds (all, and without floors) and the cloth's edge length.
    std::vector<Prepared> prepared;
    prepared.reserve(meshes.size());
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    Vec3 slo = lo, shi = hi;
    double cloth_edge = 0;
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        prepared.push_back(prepare(meshes[i], i));
        const bool floor = meshes[i].surface == Surface::FLOOR;
        if (meshes[i].surface == Surface::CLOTH) cloth_edge = std::max(cloth_edge, prepared.back().longest_edge);
        for (int f : prepared.back().faces)
            for (int k = 0; k < 3; ++k) {
                const Vec3& v = meshes[i].mesh.vertices[meshes[i].mesh.faces[f][k]];
                lo = lo.cwiseMin(v);
                hi = hi.cwiseMax(v);
                if (!floor) {
                    slo = slo.cwiseMin(v);
                    shi = shi.cwiseMax(v);
                }
            }
    }
    if (!(shi.array() >= slo.array()).all()) {
        slo = lo;
        shi = hi;
    }
    const bool have_bounds = (hi.array() >= lo.array()).all();
    const double scene_size = have_bounds ? std::max((hi - lo).norm(), 1e-9) : 1.0;
    const double epsilon = 2e-5 * std::max(scene_size, have_bounds ? (camera.eye - lo).norm() : 0.0);
    const Vec3 subject_centre = have_bounds ? Vec3(0.5 * (slo + shi)) : Vec3::Zero();
    const double subject_radius = have_bounds ? std::max(0.5 * (shi - slo).norm(), 1e-6) : 1.0;
    const double ao_distance = options.ao_distance_m > 0 ? options.ao_distance_m : 0.2 * subject_radius;
    const double priority = options.cloth_priority_m > 0 ? options.cloth_priority_m : options.cloth_priority_m == 0 ? cloth_edge : 0.0;

    DeviceHandle device(rtcNewDevice(nullptr));
    if (!device) throw RuntimeError("render: cannot create an Embree device");
    Scenes sc;
    sc.all.reset(rtcNewScene(device.get()));
    sc.cloth.reset(rtcNewScene(device.get()));
    sc.solid.reset(rtcNewScene(device.get()));
    check(device.get(), "rtcNewScene");
    std::vector<int> solid_to_mesh;
    for (RTCScene s : {sc.all.get(), sc.cloth.get(), sc.solid.get()}) rtcSetSceneFlags(s, RTC_SCENE_FLAG_ROBUST);
    for (std::size_t i = 0; i < prepared.size(); ++i) {
        if (prepared[i].faces.empty()) continue;
        const int mi = static_cast<int>(i);
        attach(device.get(), sc.all.get(), meshes[i], prepared[i], sc.all_to_mesh, mi);
        if (meshes[i].surface == Surface::CLOTH)
            attach(device.get(), sc.cloth.get(), meshes[i], prepared[i], sc.cloth_to_mesh, mi);
        else
            attach(device.get(), sc.solid.get(), meshes[i], prepared[i], solid_to_mesh, mi);
    }
    for (RTCScene s : {sc.all.get(), sc.cloth.get(), sc.solid.get()}) rtcCommitScene(s);
    check(device.get(), "rtcCommitScene");
    // All cloth faces as one mesh, for closest-point queries (Embree point queries in MeshObstacle).
    std::unique_ptr<geometry::MeshObstacle> cloth_near, solid_near;
    const RenderMesh* first_cloth = nullptr;
    for (const RenderMesh& m : meshes)
        if (m.surface == Surface::CLOTH && !first_cloth) first_cloth = &m;
    if (priority > 0) {
        geometry::TriangleMesh all_cloth;
        for (std::size_t i = 0; i < meshes.size(); ++i) {
            if (meshes[i].surface != Surface::CLOTH) continue;
            const int base = static_cast<int>(all_cloth.vertices.size());
            all_cloth.vertices.insert(all_cloth.vertices.end(), meshes[i].mesh.vertices.begin(), meshes[i].mesh.vertices.end());
            for (int f : prepared[i].faces) all_cloth.faces.push_back(meshes[i].mesh.faces[f] + Eigen::Vector3i::Constant(base));
        }
        geometry::TriangleMesh all_solid;
        for (std::size_t i = 0; i < meshes.size(); ++i) {
            if (meshes[i].surface != Surface::SOLID) continue;
            const int base = static_cast<int>(all_solid.vertices.size());
            all_solid.vertices.insert(all_solid.vertices.end(), meshes[i].mesh.vertices.begin(), meshes[i].mesh.vertices.end());
            for (int f : prepared[i].faces) all_solid.faces.push_back(meshes[i].mesh.faces[f] + Eigen::Vector3i::Constant(base));
        }
        try {
            if (!all_cloth.faces.empty() && !all_solid.faces.empty()) {
                cloth_near = std::make_unique<geometry::MeshObstacle>(std::move(all_cloth));
                solid_near = std::make_unique<geometry::MeshObstacle>(std::move(all_solid));
            }
        } catch (const InputError&) {  // e.g. a cloth of zero area: nothing lies on anything
            cloth_near.reset();
        }
    }
    const double inf = std::numeric_limits<double>::infinity();
    // Multipliers that permute the strata (coprime with spp) for the light and occlusion rays.
    auto coprime = [spp](int start) {
        int m = start;
        while (std::gcd(m, spp) != 1) ++m;
        return m;
    };
    const int mul_light = coprime(7), mul_ao = coprime(5);

    // One camera sample along dir; (r0, r1) and (r2, r3): stratified numbers for the light and
    // the occlusion ray.
    auto shade = [&](const Vec3& dir_in, double r0, double r1, double r2, double r3) -> Vec3 {
        Hit h = intersect(sc.all.get(), sc.all_to_mesh, camera.eye, dir_in, inf);
        if (!h.found) return options.background;
        Vec3 dir = dir_in;
        const RenderMesh* covered_by = nullptr;
        if (priority > 0 && meshes[h.mesh].surface != Surface::CLOTH) {
            const Hit c = intersect(sc.cloth.get(), sc.cloth_to_mesh, camera.eye, dir, h.t + priority);
            if (c.found) {
                h = c;
            } else if (cloth_near && meshes[h.mesh].surface == Surface::SOLID) {
                // Where the obstacle pokes out past the cloth's silhouette (the ray grazes the
                // poke and never meets the cloth behind it), an obstacle point within the
                // priority distance of the cloth, where the cloth lies on the obstacle (within a
                // quarter of it), is under the cloth: show the cloth there. A hem hanging near
                // an obstacle does not lie on it and stays as it is.
                const Vec3 p = camera.eye + h.t * dir;
                const geometry::ClosestPoint cp = cloth_near->closest(p);
                if (std::abs(cp.distance) < priority && solid_near->closest(cp.point).distance < 0.25 * priority) {
                    const Vec3 d2 = (cp.point - camera.eye).normalized();
                    const Hit c2 = intersect(sc.cloth.get(), sc.cloth_to_mesh, camera.eye, d2, inf);
                    if (c2.found) {
                        h = c2;
                        dir = d2;
                    } else {
                        covered_by = first_cloth;  // the cloth's silhouette itself: its colour on the obstacle's shape
                    }
                }
            }
        }
        const Prepared& p = prepared[h.mesh];
        const RenderMesh& rm = meshes[h.mesh];
        const bool cloth = rm.surface == Surface::CLOTH;
        const Eigen::Vector3i& t = rm.mesh.faces[p.faces[h.prim]];
        const double b1 = h.u, b2 = h.v, b0 = 1 - b1 - b2;
        const Vec3 pos = b0 * rm.mesh.vertices[t[0]] + b1 * rm.mesh.vertices[t[1]] + b2 * rm.mesh.vertices[t[2]];
        Vec3 ng = p.face_normals[h.prim];
        if (ng.squaredNorm() == 0) ng = -dir;
        double side = 1;
        if (ng.dot(dir) > 0) side = -1;  // two-sided: face the viewer
        ng *= side;
        const std::array<Vec3, 3> vn = {side * p.corner_normals[h.prim][0], side * p.corner_normals[h.prim][1],
                                        side * p.corner_normals[h.prim][2]};
        Vec3 ns = b0 * vn[0] + b1 * vn[1] + b2 * vn[2];
        ns = ns.squaredNorm() > 1e-24 ? Vec3(ns.normalized()) : ng;
        if (ns.dot(dir) > 0) ns = (ns - 1.01 * ns.dot(dir) * dir).normalized();  // keep it visible
        const bool back = cloth && side < 0;                                     // the underside (inside of a fold) of the cloth

        // Albedo: the cloth's thread lines (box-filtered over the sample's footprint).
        Vec3 albedo = covered_by ? covered_by->color : rm.color;
        if (cloth && p.has_uv && p.threads_per_metre > 0 && options.pattern > 0) {
            const double distance = h.t;
            const double cos_view = std::max(0.15, std::abs(ng.dot(dir)));
            const double footprint = distance * pixel_angle / grid / cos_view * p.threads_per_metre;
            const Eigen::Vector2d uv = b0 * rm.uv[t[0]] + b1 * rm.uv[t[1]] + b2 * rm.uv[t[2]];
            if (uv.allFinite()) {
                const double warp = line_coverage(uv.x(), footprint), weft = line_coverage(uv.y(), footprint);
                albedo *= (1 - options.pattern * kWarpLine * warp) * (1 - options.pattern * kWeftLine * weft);
            }
        }
        if (back) albedo *= kClothBackShade;

        // Ray origins off the surface; for the cloth, the shadow-terminator fix of Hanika (2021,
        // "Hacking the shadow terminator"): start from where the vertex tangent planes put the
        // smooth surface, so flat triangles do not shadow themselves in steps along folds.
        Vec3 org = pos;
        if (cloth) {
            Vec3 off = Vec3::Zero();
            const double bw[3] = {b0, b1, b2};
            for (int k = 0; k < 3; ++k) {
                Vec3 d = pos - rm.mesh.vertices[t[k]];
                const double dn = d.dot(vn[k]);
                if (dn < 0) d -= dn * vn[k];
                off += bw[k] * (rm.mesh.vertices[t[k]] + d);
            }
            org = off;
        }
        org += epsilon * ng;
        // From the cloth, obstacles closer than the priority distance do not occlude (they poke
        // through it between particles); everything else does.
        auto blocked = [&](const Vec3& d, double tfar) {
            if (cloth && priority > 0)
                return occluded(sc.cloth.get(), org, d, epsilon, tfar)
                    || (priority < tfar && occluded(sc.solid.get(), org, d, priority, tfar));
            return occluded(sc.all.get(), org, d, epsilon, tfar);
        };

        // Key light: a disc of angular radius light_radius_deg, one stratified direction.
        double key = 0;
        if (ns.dot(light) > 0 && ng.dot(light) > -0.2) {
            const double ct = 1 - r0 * (1 - cos_light), st = std::sqrt(std::max(0.0, 1 - ct * ct));
            const double ph = 2 * std::numbers::pi * r1;
            const Vec3 l = (ct * light + st * (std::cos(ph) * light_t + std::sin(ph) * light_b)).normalized();
            key = std::max(0.0, ns.dot(l));
            if (key > 0 && options.shadows && (ng.dot(l) <= 0 || blocked(l, inf))) key = 0;
        }
        // Sky: cosine-weighted over the hemisphere of ns, one stratified occlusion ray.
        double sky = 0.75 + 0.25 * ns.z();
        if (options.ambient_occlusion) {
            Vec3 tt, bb;
            frame_around(ns, tt, bb);
            const double rr = std::sqrt(r2), ph = 2 * std::numbers::pi * r3;
            Vec3 d = rr * std::cos(ph) * tt + rr * std::sin(ph) * bb + std::sqrt(std::max(0.0, 1 - r2)) * ns;
            if (d.dot(ng) <= 1e-3) d = (d - (d.dot(ng) - 1e-3) * ng).normalized();
            if (blocked(d, ao_distance)) sky = 0;
        }
        Vec3 c = albedo * (options.light * key + options.sky * sky);
        if (rm.surface == Surface::FLOOR) {
            const double r = (pos - subject_centre).head<2>().norm() / subject_radius;
            const double fade = std::clamp((r - kFloorFadeStart) / (kFloorFadeEnd - kFloorFadeStart), 0.0, 1.0);
            const double s = fade * fade * (3 - 2 * fade);
            c = (1 - s) * c + s * options.background;
        }
        return c;
    };

    Image image;
    image.width = W;
    image.height = H;
    image.rgb.assign(static_cast<std::size_t>(W) * H * 3, 0);
    // Rows begun, reported by whichever thread starts a row while no report is being made.
    std::atomic<int> rows_begun{0};
    std::atomic<bool> reporting{false};
#pragma omp parallel for schedule(dynamic, 1)
    for (int py = 0; py < H; ++py) {
        if (options.progress && !reporting.exchange(true)) {
            options.progress(static_cast<double>(rows_begun.load()) / H);
            reporting = false;
        }
        rows_begun.fetch_add(1);
        for (int px = 0; px < W; ++px) {
            Vec3 sum = Vec3::Zero();
            // Per pixel, random rotations (Cranley-Patterson) of fixed stratified patterns:
            // the pixel position, the light and the occlusion directions use different
            // orders of the strata so that they do not correlate.
            const double rot[6] = {hash01(px, py, 0), hash01(px, py, 1), hash01(px, py, 2),
                                   hash01(px, py, 3), hash01(px, py, 4), hash01(px, py, 5)};
            for (int s = 0; s < spp; ++s) {
                auto strat = [&](int idx, int axis, double r) {
                    const int cell = axis == 0 ? idx % grid : (idx / grid) % grid;
                    const double v = (cell + 0.5) / grid + r;
                    return v - std::floor(v);
                };
                double ox = 0.5, oy = 0.5;
                if (spp > 1) {
                    ox = strat(s, 0, rot[0] / grid);
                    oy = strat(s, 1, rot[1] / grid);
                }
                const int sl = (s * mul_light + 3) % spp, sa = (s * mul_ao + 1) % spp;
                const double r0 = strat(sl, 0, rot[2]), r1 = strat(sl, 1, rot[3]);
                const double r2 = strat(sa, 0, rot[4]), r3 = strat(sa, 1, rot[5]);
                const double sx = (2 * (px + ox) / W - 1) * tan_half * aspect;
                const double sy = (1 - 2 * (py + oy) / H) * tan_half;
                const Vec3 dir = (forward + sx * right + sy * up).normalized();
                sum += shade(dir, r0, r1, r2, r3);
            }
            sum /= spp;
            std::uint8_t* out = &image.rgb[(static_cast<std::size_t>(py) * W + px) * 3];
            for (int k = 0; k < 3; ++k) out[k] = to_srgb8(sum[k]);
        }
    }
    return image;
}

}  // namespace woven::render
