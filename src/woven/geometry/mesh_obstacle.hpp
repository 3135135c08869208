#pragma once
// An obstacle given as a triangle mesh (e.g. a chair from an OBJ file), queried through an
// Embree BVH so that closest-point and segment queries cost O(log faces).
#include <memory>
#include <vector>

#include "woven/geometry/obstacle.hpp"

namespace woven::geometry {

/// A triangle-mesh obstacle.
///
/// Closed meshes (is_closed(): every edge shared by exactly two faces with opposite
/// orientation) bound a solid and get a signed distance (< 0 inside), the sign taken from the
/// angle-weighted pseudo-normal of the closest feature (Baerentzen & Aanaes 2005). A closed mesh
/// whose faces all point inward is accepted and treated as outward.
/// Open meshes are thin shells: the distance is unsigned (>= 0 everywhere, 0 only on the
/// surface) and the normal points from the surface towards the query point.
///
/// Zero-area faces are ignored by the queries. The BVH stores single-precision vertices; the
/// distances, closest points and contact parameters are computed in double precision on the
/// candidate triangles, with padded search radii so that the float BVH never drops the nearest
/// triangle. Not copyable (it owns Embree handles); safe to query from several threads.
class MeshObstacle : public Obstacle {
public:
    /// Throws InputError for an empty mesh ("vertices"/"faces"), a non-finite vertex
    /// ("vertices"), a face index out of range ("faces") or a mesh of zero total area ("faces").
    /// Throws RuntimeError if Embree fails.
    explicit MeshObstacle(TriangleMesh mesh);
    ~MeshObstacle() override;
    MeshObstacle(const MeshObstacle&) = delete;
    MeshObstacle& operator=(const MeshObstacle&) = delete;

    ClosestPoint closest(const Vec3& p) const override;
    /// Segment query by an Embree ray (rtcIntersect1) with a hit filter: for a closed mesh the
    /// first face entered (0 if p0 is inside), for an open one the first face crossed.
    std::optional<double> first_contact(const Vec3& p0, const Vec3& p1) const override;
    Aabb bounds() const override { return bounds_; }
    /// The mesh itself (faces reversed if it was closed and inward-facing).
    TriangleMesh tessellate() const override;
    std::string kind() const override { return "mesh"; }

    /// True for a closed, consistently oriented mesh (signed distance).
    bool closed() const { return closed_; }
    /// The mesh as given.
    const TriangleMesh& mesh() const { return mesh_; }

private:
    friend struct MeshQueryAccess;  // the Embree callbacks in the .cpp
    struct Embree;
    struct FaceData {
        Vec3 normal;          // outward unit face normal (zero for a zero-area face)
        Vec3 edge_normal[3];  // pseudo-normal of edge (k, k+1)
    };
    TriangleMesh mesh_;
    bool closed_ = false;
    double orientation_ = 1.0;      // -1 for a closed mesh whose faces point inward
    Vec3 origin_;                   // local origin of the float BVH (centre of the bounds)
    double pad_ = 0;                // m: padding for float round-off in BVH queries
    Aabb bounds_;
    std::vector<int> prim_to_face_;  // Embree primitive -> face (zero-area faces dropped)
    std::vector<FaceData> face_data_;
    std::vector<Vec3, Eigen::aligned_allocator<Vec3>> vertex_normal_;  // angle-weighted pseudo-normals
    std::unique_ptr<Embree> embree_;
};

}  // namespace woven::geometry
