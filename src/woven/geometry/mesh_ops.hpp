#pragma once
// Operations on triangle meshes: the cloth grid as a mesh, normals, placement in the scene and
// topology checks.
#include "woven/common/types.hpp"
#include "woven/geometry/triangle_mesh.hpp"

namespace woven::geometry {

/// The cloth grid (nu * nv positions, index i + nu * j, m) as triangles, two per cell:
/// (i, j) (i+1, j) (i+1, j+1) and (i, j) (i+1, j+1) (i, j+1). InputError when the sizes do not
/// match or nu or nv < 2.
TriangleMesh grid_mesh(const Positions& x, int nu, int nv);

/// Unit normals per vertex: the sum of the normals of the faces around it weighted by their
/// areas; (0, 0, 1) for a vertex no face with an area touches.
Positions vertex_normals(const TriangleMesh& mesh);

/// The mesh scaled by `scale` about the origin, then rotated by rotation_deg (degrees) about x,
/// then about y, then about z (fixed axes), then translated by `translate` (m).
/// Faces are unchanged (scale must be > 0 to keep them outward; not checked here).
TriangleMesh transform(const TriangleMesh& mesh, double scale, const Vec3& rotation_deg, const Vec3& translate);

/// True when every edge is shared by exactly two faces that traverse it in opposite directions
/// (a closed, consistently oriented surface). Faces with an index out of range make it false.
bool is_closed(const TriangleMesh& mesh);

/// Volume enclosed by a closed mesh (m^3): positive when the faces are counter-clockwise seen
/// from outside, negative when they all face inward. Meaningless for an open mesh.
double signed_volume(const TriangleMesh& mesh);

}  // namespace woven::geometry
