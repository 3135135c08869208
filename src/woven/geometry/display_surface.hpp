#pragma once
// A surface for display lifted off the obstacles: a cloth's particles keep the solver's contact
// distance from an obstacle, but the flat triangles between them cut an obstacle's edge (a cube's
// top edge under a cloth with 2 cm spacing pokes through by up to ~7 mm). The physical mesh is
// left as it is; this moves a copy's vertices so that the triangles clear the obstacles.
#include "woven/geometry/obstacle.hpp"
#include "woven/geometry/triangle_mesh.hpp"

namespace woven::geometry {

struct LiftedSurface {
    TriangleMesh mesh;    ///< the same faces, the vertices moved
    double max_lift = 0;  ///< the largest vertex move (m)
};

/// Moves the vertices of `mesh` off `obstacles` until every triangle, sampled at `samples` + 1
/// points along each edge or more (barycentric grid; samples at most 2 clearances apart, up to
/// 49 per edge), lies at least `clearance` (m) from them, in at most
/// `rounds` rounds: each triangle short of the clearance pushes its three vertices along the
/// outward normal of the obstacle at its worst sample, by the shortfall (a vertex takes the
/// largest push of its triangles). Vertices of clear triangles stay.
LiftedSurface lift_off_obstacles(const TriangleMesh& mesh, const ObstacleSet& obstacles, double clearance, int samples = 6,
                                 int rounds = 8);

/// The smallest signed distance (m) of `mesh`'s triangles to `obstacles`, sampled as above.
double min_sampled_distance(const TriangleMesh& mesh, const ObstacleSet& obstacles, int samples);

}  // namespace woven::geometry
