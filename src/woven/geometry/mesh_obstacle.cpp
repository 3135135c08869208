#include "woven/geometry/mesh_obstacle.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <mutex>
#include <unordered_map>

#include <embree3/rtcore.h>

#include "woven/common/error.hpp"
#include "woven/geometry/mesh_ops.hpp"

namespace woven::geometry {
namespace {

/// One Embree device shared by all mesh obstacles alive at a time.
std::shared_ptr<RTCDeviceTy> shared_device()
{
    static std::mutex mutex;
    static std::weak_ptr<RTCDeviceTy> weak;
    std::lock_guard lock(mutex);
    if (auto d = weak.lock()) return d;
    RTCDevice raw = rtcNewDevice(nullptr);
    if (!raw) throw RuntimeError("embree: cannot create a device (error " + std::to_string(rtcGetDeviceError(nullptr)) + ")");
    std::shared_ptr<RTCDeviceTy> d(raw, [](RTCDevice x) { rtcReleaseDevice(x); });
    weak = d;
    return d;
}

/// Feature of a triangle that holds the closest point.
enum class Feature { vertex0, vertex1, vertex2, edge01, edge12, edge20, face };

/// Closest point on triangle (a, b, c) to p (Ericson, Real-Time Collision Detection, 5.1.5).
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, Feature& feature)
{
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) {
        feature = Feature::vertex0;
        return a;
    }
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) {
        feature = Feature::vertex1;
        return b;
    }
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        feature = Feature::edge01;
        return a + (d1 / (d1 - d3)) * ab;
    }
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) {
        feature = Feature::vertex2;
        return c;
    }
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        feature = Feature::edge20;
        return a + (d2 / (d2 - d6)) * ac;
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        feature = Feature::edge12;
        return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
    }
    const double denom = 1.0 / (va + vb + vc);
    feature = Feature::face;
    return a + ab * (vb * denom) + ac * (vc * denom);
}

}  // namespace

struct MeshObstacle::Embree {
    std::shared_ptr<RTCDeviceTy> device;
    RTCScene scene = nullptr;
    ~Embree()
    {
        if (scene) rtcReleaseScene(scene);
    }
};

/// The Embree callbacks: closest point (rtcPointQuery) and the hit filter of first_contact.
struct MeshQueryAccess {
    struct PointQuery {
        const MeshObstacle* self;
        Vec3 p;
        double best_d2 = std::numeric_limits<double>::infinity();
        int face = -1;
        Feature feature = Feature::face;
        Vec3 point = Vec3::Zero();
    };

    static bool point_callback(RTCPointQueryFunctionArguments* args)
    {
        auto* q = static_cast<PointQuery*>(args->userPtr);
        const MeshObstacle& m = *q->self;
        const int f = m.prim_to_face_[args->primID];
        const auto& idx = m.mesh_.faces[f];
        Feature feature;
        const Vec3 c = closest_on_triangle(q->p, m.mesh_.vertices[idx[0]], m.mesh_.vertices[idx[1]], m.mesh_.vertices[idx[2]],
                                           feature);
        const double d2 = (q->p - c).squaredNorm();
        if (d2 >= q->best_d2) return false;
        q->best_d2 = d2;
        q->face = f;
        q->feature = feature;
        q->point = c;
        const float r = static_cast<float>(std::sqrt(d2) + q->self->pad_ + 1e-6 * (q->p - m.origin_).lpNorm<Eigen::Infinity>());
        if (r < args->query->radius) {
            args->query->radius = r;
            return true;
        }
        return false;
    }

    struct RayQuery {
        const MeshObstacle* self;
        Vec3 p0, d;
    };
    struct RayContext {
        RTCIntersectContext context;  // first member: Embree hands back a pointer to it
        const RayQuery* query;
    };

    /// Exact (double) ray parameter of the plane of face f for p0 + t d; NaN if parallel.
    static double plane_t(const MeshObstacle& m, int f, const Vec3& p0, const Vec3& d)
    {
        const Vec3& n = m.face_data_[f].normal;
        const double nd = n.dot(d);
        if (nd == 0) return std::numeric_limits<double>::quiet_NaN();
        return n.dot(m.mesh_.vertices[m.mesh_.faces[f][0]] - p0) / nd;
    }

    static bool acceptable(const MeshObstacle& m, int f, const Vec3& p0, const Vec3& d)
    {
        if (m.closed_ && m.face_data_[f].normal.dot(d) >= 0) return false;  // leaving the solid
        const double t = plane_t(m, f, p0, d);
        return t >= 0 && t <= 1;  // false for NaN
    }

    static void filter(const RTCFilterFunctionNArguments* args)
    {
        const auto* ctx = reinterpret_cast<const RayContext*>(args->context);
        const RayQuery& q = *ctx->query;
        for (unsigned i = 0; i < args->N; ++i) {
            if (!args->valid[i]) continue;
            const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
            if (!acceptable(*q.self, q.self->prim_to_face_[prim], q.p0, q.d)) args->valid[i] = 0;
        }
    }
};

MeshObstacle::MeshObstacle(TriangleMesh mesh) : mesh_(std::move(mesh))
{
    if (mesh_.vertices.empty()) throw InputError("", "vertices", "a non-empty mesh expected");
    if (mesh_.faces.empty()) throw InputError("", "faces", "a mesh with at least one face expected");
    const int nv = static_cast<int>(mesh_.vertices.size());
    for (const Vec3& v : mesh_.vertices) {
        if (!v.allFinite()) throw InputError("", "vertices", "finite coordinates expected");
        bounds_.extend(v);
    }
    for (const auto& f : mesh_.faces) {
        if (f.minCoeff() < 0 || f.maxCoeff() >= nv) {
            throw InputError("", "faces", "vertex indices in [0, " + std::to_string(nv) + ") expected");
        }
    }
    closed_ = is_closed(mesh_);
    if (closed_ && signed_volume(mesh_) < 0) orientation_ = -1.0;
    origin_ = 0.5 * (bounds_.lo + bounds_.hi);
    pad_ = 1e-6 * std::max(1.0, (bounds_.hi - bounds_.lo).lpNorm<Eigen::Infinity>()) + 1e-9;

    // Face normals, edge and vertex pseudo-normals.
    const std::size_t nf = mesh_.faces.size();
    face_data_.resize(nf);
    vertex_normal_.assign(nv, Vec3::Zero());
    std::unordered_map<std::uint64_t, Vec3> edge_sum;
    auto edge_key = [](std::int64_t a, std::int64_t b) {
        if (a > b) std::swap(a, b);
        return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint64_t>(b);
    };
    double area = 0;
    for (std::size_t i = 0; i < nf; ++i) {
        const auto& f = mesh_.faces[i];
        const Vec3 n = (mesh_.vertices[f[1]] - mesh_.vertices[f[0]]).cross(mesh_.vertices[f[2]] - mesh_.vertices[f[0]]);
        const double len = n.norm();
        area += 0.5 * len;
        face_data_[i].normal = len > 0 ? Vec3(orientation_ * n / len) : Vec3(Vec3::Zero());
        if (len > 0) prim_to_face_.push_back(static_cast<int>(i));
        const Vec3& fn = face_data_[i].normal;
        for (int k = 0; k < 3; ++k) {
            const int a = f[k], b = f[(k + 1) % 3], c = f[(k + 2) % 3];
            edge_sum.try_emplace(edge_key(a, b), Vec3::Zero()).first->second += fn;
            if (len > 0) {
                const Vec3 e1 = (mesh_.vertices[b] - mesh_.vertices[a]).normalized();
                const Vec3 e2 = (mesh_.vertices[c] - mesh_.vertices[a]).normalized();
                const double angle = std::acos(std::clamp(e1.dot(e2), -1.0, 1.0));
                if (std::isfinite(angle)) vertex_normal_[a] += angle * fn;
            }
        }
    }
    if (!(area > 0)) throw InputError("", "faces", "a mesh of non-zero area expected");
    for (std::size_t i = 0; i < nf; ++i) {
        const auto& f = mesh_.faces[i];
        for (int k = 0; k < 3; ++k) face_data_[i].edge_normal[k] = edge_sum[edge_key(f[k], f[(k + 1) % 3])];
    }

    // Embree scene of the non-degenerate faces, in coordinates relative to origin_.
    embree_ = std::make_unique<Embree>();
    embree_->device = shared_device();
    RTCDevice device = embree_->device.get();
    embree_->scene = rtcNewScene(device);
    if (!embree_->scene) throw RuntimeError("embree: cannot create a scene");
    rtcSetSceneFlags(embree_->scene, RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
    rtcSetSceneBuildQuality(embree_->scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!geom) throw RuntimeError("embree: cannot create a geometry");
    auto* vb = static_cast<float*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv));
    auto* ib = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), prim_to_face_.size()));
    if (!vb || !ib) {
        rtcReleaseGeometry(geom);
        throw RuntimeError("embree: cannot allocate buffers");
    }
    for (int i = 0; i < nv; ++i) {
        const Vec3 v = mesh_.vertices[i] - origin_;
        for (int k = 0; k < 3; ++k) vb[3 * i + k] = static_cast<float>(v[k]);
    }
    for (std::size_t j = 0; j < prim_to_face_.size(); ++j) {
        const auto& f = mesh_.faces[prim_to_face_[j]];
        for (int k = 0; k < 3; ++k) ib[3 * j + k] = static_cast<unsigned>(f[k]);
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometry(embree_->scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(embree_->scene);
    if (const RTCError e = rtcGetDeviceError(device); e != RTC_ERROR_NONE) {
        throw RuntimeError("embree: building the BVH failed (error " + std::to_string(static_cast<int>(e)) + ")");
    }
}

MeshObstacle::~MeshObstacle() = default;

ClosestPoint MeshObstacle::closest(const Vec3& p) const
{
    MeshQueryAccess::PointQuery q{this, p};
    const Vec3 local = p - origin_;
    RTCPointQuery query;
    query.x = static_cast<float>(local.x());
    query.y = static_cast<float>(local.y());
    query.z = static_cast<float>(local.z());
    query.time = 0.0f;
    query.radius = std::numeric_limits<float>::infinity();
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    rtcPointQuery(embree_->scene, &query, &context, &MeshQueryAccess::point_callback, &q);
    if (q.face < 0) throw RuntimeError("embree: the closest-point query found no triangle");

    const FaceData& fd = face_data_[q.face];
    const auto& f = mesh_.faces[q.face];
    Vec3 pseudo;
    switch (q.feature) {
    case Feature::vertex0: pseudo = vertex_normal_[f[0]]; break;
    case Feature::vertex1: pseudo = vertex_normal_[f[1]]; break;
    case Feature::vertex2: pseudo = vertex_normal_[f[2]]; break;
    case Feature::edge01: pseudo = fd.edge_normal[0]; break;
    case Feature::edge12: pseudo = fd.edge_normal[1]; break;
    case Feature::edge20: pseudo = fd.edge_normal[2]; break;
    default: pseudo = fd.normal; break;
    }
    const Vec3 diff = p - q.point;
    const double d = std::sqrt(q.best_d2);
    double sign = 1.0;
    if (closed_ && diff.dot(pseudo) < 0) sign = -1.0;
    Vec3 normal;
    if (d > 0) {
        normal = sign * diff / d;
    } else {
        const double len = pseudo.norm();
        normal = len > 0 ? Vec3(pseudo / len) : Vec3(fd.normal);
    }
    return {sign * d, q.point, normal};
}

std::optional<double> MeshObstacle::first_contact(const Vec3& p0, const Vec3& p1) const
{
    if (closed_ && distance(p0) <= 0) return 0.0;
    const Vec3 d = p1 - p0;
    const double length = d.norm();
    if (length == 0) return distance(p0) <= 0 ? std::optional<double>(0.0) : std::nullopt;
    // Start the float ray a little behind p0 and end it a little past p1, so that float round-off
    // cannot drop a face near either end; the filter decides in double precision.
    const double back = (pad_ + 1e-6 * (p0 - origin_).lpNorm<Eigen::Infinity>()) / length;
    const Vec3 org = p0 - origin_ - back * d;
    MeshQueryAccess::RayQuery rq{this, p0, d};
    MeshQueryAccess::RayContext ctx;
    rtcInitIntersectContext(&ctx.context);
    ctx.context.filter = &MeshQueryAccess::filter;
    ctx.query = &rq;
    RTCRayHit rh;
    rh.ray.org_x = static_cast<float>(org.x());
    rh.ray.org_y = static_cast<float>(org.y());
    rh.ray.org_z = static_cast<float>(org.z());
    rh.ray.dir_x = static_cast<float>(d.x());
    rh.ray.dir_y = static_cast<float>(d.y());
    rh.ray.dir_z = static_cast<float>(d.z());
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = static_cast<float>((1.0 + 2.0 * back) * (1.0 + 1e-6));
    rh.ray.time = 0.0f;
    rh.ray.mask = 0xffffffffu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(embree_->scene, &ctx.context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    const double t = MeshQueryAccess::plane_t(*this, prim_to_face_[rh.hit.primID], p0, d);
    return std::clamp(t, 0.0, 1.0);
}

TriangleMesh MeshObstacle::tessellate() const
{
    TriangleMesh m = mesh_;
    if (orientation_ < 0) {
        for (auto& f : m.faces) std::swap(f[1], f[2]);
    }
    return m;
}

}  // namespace woven::geometry
