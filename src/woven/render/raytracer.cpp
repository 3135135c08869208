#include "woven/render/raytracer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>

#include <Eigen/Geometry>
#include <embree3/rtcore.h>

#include "woven/common/error.hpp"

namespace woven::render {

namespace {

constexpr double kPi = 3.14159265358979323846;

Vec3 any_perpendicular(const Vec3& v)
{
    const Vec3 a = std::abs(v.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    return v.cross(a).normalized();
}

/// Mesh data prepared for shading; faces with non-finite vertices are dropped.
struct Prepared {
    const RenderMesh* source = nullptr;
    std::vector<int> faces;                      // Embree primID -> face index
    std::vector<Vec3> face_normals;              // per kept face (unit, zero if degenerate)
    std::vector<std::array<Vec3, 3>> corner_normals;  // per kept face
    bool has_uv = false;
    double threads_per_metre = 0;                // uv length per world length
};

Prepared prepare(const RenderMesh& rm, std::size_t index)
{
    Prepared p;
    p.source = &rm;
    const auto& V = rm.mesh.vertices;
    const auto& F = rm.mesh.faces;
    const int nv = static_cast<int>(V.size());
    std::vector<Vec3> area_normals;  // unnormalised, |n| = 2 * area
    for (std::size_t f = 0; f < F.size(); ++f) {
        const Eigen::Vector3i& t = F[f];
        for (int k = 0; k < 3; ++k)
            if (t[k] < 0 || t[k] >= nv)
                throw InputError("render", "mesh " + std::to_string(index),
                                 "face " + std::to_string(f) + " has a vertex index out of range");
        if (!V[t[0]].allFinite() || !V[t[1]].allFinite() || !V[t[2]].allFinite()) continue;
        p.faces.push_back(static_cast<int>(f));
        const Vec3 n = (V[t[1]] - V[t[0]]).cross(V[t[2]] - V[t[0]]);
        area_normals.push_back(n);
        const double len = n.norm();
        p.face_normals.push_back(len > 0 ? Vec3(n / len) : Vec3::Zero());
    }

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
    const double crease_cos = rm.cloth ? -2.0 : std::cos(40.0 * kPi / 180.0);
    p.corner_normals.resize(p.faces.size());
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

    p.has_uv = rm.uv.size() == V.size() && !V.empty();
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

/// Plain-weave brightness at thread coordinates (u, v), before normalisation; about 0.83..1.
double weave_shade(double u, double v)
{
    const double iu = std::floor(u), iv = std::floor(v);
    const double fu = u - iu, fv = v - iv;
    const bool warp_on_top = (static_cast<long long>(iu) + static_cast<long long>(iv)) % 2 == 0;
    const double across = warp_on_top ? fu : fv;   // position across the visible thread
    const double along = warp_on_top ? fv : fu;    // position along it (dips at the crossings)
    const double x = 2 * across - 1;
    const double profile = std::sqrt(std::max(0.0, 1 - x * x));
    const double dip = 0.85 + 0.15 * std::sin(kPi * along);
    const double tint = warp_on_top ? 1.0 : 0.97;
    return tint * (0.86 + 0.14 * profile * dip);
}

double weave_mean()
{
    static const double mean = [] {
        const int n = 128;
        double s = 0;
        for (int i = 0; i < 2 * n; ++i)
            for (int j = 0; j < 2 * n; ++j) s += weave_shade((i + 0.5) / n, (j + 0.5) / n);
        return s / (4.0 * n * n);
    }();
    return mean;
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

double jitter(int px, int py, int s, int axis)
{
    std::uint32_t h = hash32(static_cast<std::uint32_t>(px) * 0x9E3779B1U ^ hash32(static_cast<std::uint32_t>(py) + 0x85EBCA77U));
    h = hash32(h ^ (static_cast<std::uint32_t>(s) * 0xC2B2AE3DU + static_cast<std::uint32_t>(axis)));
    return (h >> 8) * (1.0 / 16777216.0);
}

struct DeviceDeleter { void operator()(RTCDevice d) const { rtcReleaseDevice(d); } };
struct SceneDeleter { void operator()(RTCScene s) const { rtcReleaseScene(s); } };
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
    const double az = azimuth_deg * kPi / 180.0, el = elevation_deg * kPi / 180.0;
    const Vec3 dir(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    const double half_fov = 0.5 * cam.fov_deg * kPi / 180.0;
    const double limit = 0.9 * std::tan(half_fov);  // keep the box within 90 % of the half height
    // Grow from the bounding-sphere distance until the box fits, then bisect for the closest distance at which the
    // eight corners fit both vertically and horizontally (so any aspect >= 1 frames it).
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

Image render(const std::vector<RenderMesh>& meshes, const Camera& camera, const RenderOptions& options)
{
    const int W = options.width, H = options.height;
    if (W < 1 || W > 16384 || H < 1 || H > 16384)
        throw InputError("render", "size", "width and height in 1..16384 pixels");
    if (!(camera.fov_deg > 0 && camera.fov_deg < 179))
        throw InputError("render", "camera.fov_deg", "a field of view in (0, 179) degrees");
    const Vec3 forward_raw = camera.target - camera.eye;
    if (!camera.eye.allFinite() || !forward_raw.allFinite() || forward_raw.norm() <= 0)
        throw InputError("render", "camera", "finite eye and target at distinct points");
    if (!options.light_dir.allFinite() || options.light_dir.norm() <= 0)
        throw InputError("render", "light_dir", "a finite non-zero direction");
    const int spp = std::max(1, options.samples_per_pixel);
    const Vec3 light = options.light_dir.normalized();

    // Camera basis.
    const Vec3 forward = forward_raw.normalized();
    Vec3 right = forward.cross(camera.up);
    right = right.norm() > 1e-9 * std::max(1.0, camera.up.norm()) ? Vec3(right.normalized()) : any_perpendicular(forward);
    const Vec3 up = right.cross(forward);
    const double tan_half = std::tan(0.5 * camera.fov_deg * kPi / 180.0);
    const double aspect = static_cast<double>(W) / H;
    const double pixel_angle = 2 * tan_half / H;  // world size of a pixel at unit distance

    // Prepare meshes and the Embree scene.
    std::vector<Prepared> prepared;
    prepared.reserve(meshes.size());
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (std::size_t i = 0; i < meshes.size(); ++i) {
        prepared.push_back(prepare(meshes[i], i));
        for (int f : prepared.back().faces)
            for (int k = 0; k < 3; ++k) {
                const Vec3& v = meshes[i].mesh.vertices[meshes[i].mesh.faces[f][k]];
                lo = lo.cwiseMin(v);
                hi = hi.cwiseMax(v);
            }
    }
    const double scene_size = (hi - lo).allFinite() ? std::max((hi - lo).norm(), 1e-9) : 1.0;
    const double epsilon = 2e-5 * std::max(scene_size, (camera.eye - (lo.allFinite() ? lo : camera.eye)).norm());

    DeviceHandle device(rtcNewDevice(nullptr));
    if (!device) throw RuntimeError("render: cannot create an Embree device");
    SceneHandle scene(rtcNewScene(device.get()));
    check(device.get(), "rtcNewScene");
    rtcSetSceneFlags(scene.get(), RTC_SCENE_FLAG_ROBUST);
    std::vector<int> geom_to_mesh;
    for (std::size_t i = 0; i < prepared.size(); ++i) {
        const Prepared& p = prepared[i];
        if (p.faces.empty()) continue;
        const auto& V = meshes[i].mesh.vertices;
        const auto& F = meshes[i].mesh.faces;
        RTCGeometry geom = rtcNewGeometry(device.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), V.size()));
        auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                  3 * sizeof(unsigned), p.faces.size()));
        check(device.get(), "rtcSetNewGeometryBuffer");
        for (std::size_t v = 0; v < V.size(); ++v)
            for (int k = 0; k < 3; ++k)
                vb[3 * v + k] = std::isfinite(V[v][k]) ? static_cast<float>(V[v][k]) : 0.0f;
        for (std::size_t j = 0; j < p.faces.size(); ++j)
            for (int k = 0; k < 3; ++k) ib[3 * j + k] = static_cast<unsigned>(F[p.faces[j]][k]);
        rtcCommitGeometry(geom);
        const unsigned id = rtcAttachGeometry(scene.get(), geom);
        rtcReleaseGeometry(geom);
        if (geom_to_mesh.size() <= id) geom_to_mesh.resize(id + 1, -1);
        geom_to_mesh[id] = static_cast<int>(i);
    }
    rtcCommitScene(scene.get());
    check(device.get(), "rtcCommitScene");
    RTCScene sc = scene.get();

    const double mean_weave = weave_mean();
    const int grid = std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(spp)))));
    const float inf = std::numeric_limits<float>::infinity();

    auto shade = [&](const Vec3& dir) -> Vec3 {
        RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        RTCRayHit rh;
        rh.ray.org_x = static_cast<float>(camera.eye.x());
        rh.ray.org_y = static_cast<float>(camera.eye.y());
        rh.ray.org_z = static_cast<float>(camera.eye.z());
        rh.ray.dir_x = static_cast<float>(dir.x());
        rh.ray.dir_y = static_cast<float>(dir.y());
        rh.ray.dir_z = static_cast<float>(dir.z());
        rh.ray.tnear = 0.0f;
        rh.ray.tfar = inf;
        rh.ray.time = 0.0f;
        rh.ray.mask = 0xFFFFFFFFu;
        rh.ray.id = 0;
        rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(sc, &ctx, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return options.background;

        const int mi = geom_to_mesh[rh.hit.geomID];
        const Prepared& p = prepared[mi];
        const RenderMesh& rm = meshes[mi];
        const int j = static_cast<int>(rh.hit.primID);
        const Eigen::Vector3i& t = rm.mesh.faces[p.faces[j]];
        const double b1 = rh.hit.u, b2 = rh.hit.v, b0 = 1 - b1 - b2;
        const Vec3 pos = b0 * rm.mesh.vertices[t[0]] + b1 * rm.mesh.vertices[t[1]] + b2 * rm.mesh.vertices[t[2]];
        Vec3 ng = p.face_normals[j];
        Vec3 ns = b0 * p.corner_normals[j][0] + b1 * p.corner_normals[j][1] + b2 * p.corner_normals[j][2];
        if (ng.squaredNorm() == 0) ng = -dir;
        ns = ns.squaredNorm() > 1e-24 ? Vec3(ns.normalized()) : ng;
        if (ng.dot(dir) > 0) {  // two-sided: face the viewer
            ng = -ng;
            ns = -ns;
        }
        if (ns.dot(dir) > 0) ns = (ns - 2 * ns.dot(dir) * dir).normalized();  // keep visible

        Vec3 albedo = rm.color;
        if (rm.cloth && p.has_uv && p.threads_per_metre > 0) {
            const double distance = (pos - camera.eye).norm();
            const double cos_view = std::max(0.2, std::abs(ng.dot(dir)));
            const double footprint = distance * pixel_angle / cos_view / grid;  // m per sample
            const double threads_per_sample = footprint * p.threads_per_metre;
            const double fade = std::clamp((0.5 - threads_per_sample) / 0.3, 0.0, 1.0);
            if (fade > 0) {
                const Eigen::Vector2d uv = b0 * rm.uv[t[0]] + b1 * rm.uv[t[1]] + b2 * rm.uv[t[2]];
                if (uv.allFinite()) albedo *= 1 + fade * (weave_shade(uv.x(), uv.y()) / mean_weave - 1);
            }
        }

        double diffuse = std::max(0.0, ns.dot(light));
        if (ng.dot(light) <= 0) diffuse = 0;
        if (diffuse > 0 && options.shadows) {
            const Vec3 org = pos + epsilon * ng;
            RTCRay ray;
            ray.org_x = static_cast<float>(org.x());
            ray.org_y = static_cast<float>(org.y());
            ray.org_z = static_cast<float>(org.z());
            ray.dir_x = static_cast<float>(light.x());
            ray.dir_y = static_cast<float>(light.y());
            ray.dir_z = static_cast<float>(light.z());
            ray.tnear = static_cast<float>(epsilon);
            ray.tfar = inf;
            ray.time = 0.0f;
            ray.mask = 0xFFFFFFFFu;
            ray.id = 0;
            ray.flags = 0;
            RTCIntersectContext sctx;
            rtcInitIntersectContext(&sctx);
            rtcOccluded1(sc, &sctx, &ray);
            if (ray.tfar < 0) diffuse = 0;
        }
        const double ambient = 0.22 + 0.08 * ns.z();
        return albedo * (ambient + 0.78 * diffuse);
    };

    Image image;
    image.width = W;
    image.height = H;
    image.rgb.assign(static_cast<std::size_t>(W) * H * 3, 0);
#pragma omp parallel for schedule(dynamic, 1)
    for (int py = 0; py < H; ++py) {
        for (int px = 0; px < W; ++px) {
            Vec3 sum = Vec3::Zero();
            for (int s = 0; s < spp; ++s) {
                double ox = 0.5, oy = 0.5;
                if (spp > 1) {
                    const int cx = s % grid, cy = (s / grid) % grid;
                    ox = (cx + jitter(px, py, s, 0)) / grid;
                    oy = (cy + jitter(px, py, s, 1)) / grid;
                }
                const double sx = (2 * (px + ox) / W - 1) * tan_half * aspect;
                const double sy = (1 - 2 * (py + oy) / H) * tan_half;
                const Vec3 dir = (forward + sx * right + sy * up).normalized();
                sum += shade(dir);
            }
            sum /= spp;
            std::uint8_t* out = &image.rgb[(static_cast<std::size_t>(py) * W + px) * 3];
            for (int k = 0; k < 3; ++k) out[k] = to_srgb8(sum[k]);
        }
    }
    return image;
}

}  // namespace woven::render
