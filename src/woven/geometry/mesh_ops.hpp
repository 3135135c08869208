#pragma once
// Operations on triangle meshes: placement in the scene and topology checks.
#include "woven/common/types.hpp"
#include "woven/geometry/triangle_mesh.hpp"

namespace woven::geometry {

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
