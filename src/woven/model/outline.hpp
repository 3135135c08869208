#pragma once
// A cloth of any outline: the particle grid cut along a disc, an annulus or a simple polygon.
// The weave keeps its directions (weft along u = x, warp along v = y, grid.hpp); the outline is
// given in the cloth's rest plane, in metres, relative to the grid's centre.
//
//   particles (o kept, . dropped) and their dual cells (sigma x sigma squares around each):
//
//         .   .   .   .   .
//         .   . _-o-_ .   .       a particle is kept when it lies inside the outline;
//         .  /o   o   o\  .       it stands for the part of its dual cell inside the outline
//         . |o    o    o| .       (m = W x that area), plus its share of the slivers of the
//         .  \o   o   o/  .       dual cells of dropped neighbours that reach inside: the
//         .   . ~-o-~ .   .       masses sum to W x the outline's area exactly
//
// The energy terms then exist only where their whole stencil is kept (stencils.hpp's mask), so
// the cut edge is a free edge.
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "woven/common/types.hpp"
#include "woven/geometry/triangle_mesh.hpp"
#include "woven/model/grid.hpp"

namespace woven::model {

/// A closed polygon (m), vertices in order, the last joined to the first.
using Ring = std::vector<Vec2>;

/// The shape a cloth is cut to.
struct Outline {
    enum class Kind {
        RECTANGLE,  ///< the whole grid (the rectangle its particles span)
        DISC,       ///< centre, radius
        ANNULUS,    ///< centre, radius, inner_radius
        POLYGON,    ///< points
    };
    Kind kind = Kind::RECTANGLE;
    Vec2 centre = Vec2::Zero();  ///< m, from the grid's centre (disc, annulus)
    double radius = 0;           ///< m (disc, annulus: outer)
    double inner_radius = 0;     ///< m (annulus: the hole)
    std::vector<Vec2> points;    ///< m, from the grid's centre (polygon), either orientation
};

/// Most points of a polygon outline: its self-intersection test compares every pair of edges
/// (0.7 s at this size; a 200,000-point outline took 285 s), so a larger one is bad input.
inline constexpr std::size_t kMaxOutlinePoints = 10000;

/// Sides of the regular polygon standing for a circle (its area made the circle's exactly).
inline constexpr int kCircleSegments = 720;

/// Checks an outline: finite numbers; radius > 0; 0 < inner_radius < radius; a polygon with
/// 3 .. kMaxOutlinePoints points, non-zero area, no repeated consecutive point and no self-intersection. Throws
/// InputError(source, field + ".<key>", ...) naming the offending key (radius_m,
/// inner_radius_m, points_m).
void validate_outline(const Outline& outline, const std::string& source, const std::string& field);

/// The outline as one counter-clockwise ring: a circle as a regular kCircleSegments-gon whose
/// area is the circle's; an annulus as a keyhole (the outer circle, a cut to the inner one
/// traversed clockwise, and back), whose area is the annulus's; a rectangle as the grid's
/// particle hull. Assumes validate_outline passed.
Ring outline_ring(const Outline& outline, const Grid& grid);

/// Signed area (m^2), > 0 for counter-clockwise.
double signed_area(const Ring& ring);

/// Whether p lies inside the ring (even-odd rule; a keyhole's double cut counts twice, so
/// not at all).
bool contains(const Ring& ring, const Vec2& p);

/// Two edges (a, b) of the ring that cross or overlap (edge k joins point k to point k+1),
/// a != b, non-adjacent edges only; nullopt when it is simple. O(n^2).
std::optional<std::pair<int, int>> self_intersection(const Ring& ring);

/// The part of the ring inside the axis-aligned box [lo, hi] (Sutherland-Hodgman): one
/// polygon, possibly with zero-width bridges along the box's sides where the ring is not
/// convex; its signed area is exactly that of ring ∩ box.
Ring clip_to_box(const Ring& ring, const Vec2& lo, const Vec2& hi);

/// The region of a polygon whose winding number is 0 or 1 (a simple ring, a keyhole, a
/// clip_to_box result with zero-width bridges) as counter-clockwise triangles, by trapezoids
/// between the vertices' x: their areas sum to the polygon's signed area.
std::vector<std::array<Vec2, 3>> triangulate(const Ring& polygon);

/// Rest position of particle (i, j) in the cloth plane relative to the grid's centre (m), as
/// flat_grid lays it out: ((i - (nu - 1) / 2) sigma, (j - (nv - 1) / 2) sigma).
Vec2 rest_uv(const Grid& grid, int i, int j);

/// What an outline keeps of a grid.
struct ClothCut {
    Ring ring;                 ///< outline_ring
    std::vector<char> active;  ///< per particle: 1 if kept (inside the outline)
    std::vector<double> area;  ///< per particle (m^2): 0 where dropped; sums to the outline's area
    int count = 0;             ///< kept particles
    double total_area = 0;     ///< m^2, the outline's area
};

/// Cuts the grid along the outline (see the sketch). Throws InputError(source, field, ...)
/// when the outline is invalid (validate_outline), reaches beyond the grid's particles,
/// encloses no particle, or is too small for the grid: a kept particle with no kept thread
/// neighbour, or no grid cell with all four corners kept.
ClothCut cut_grid(const Grid& grid, const Outline& outline, const std::string& source, const std::string& field);

/// The surface of a cut cloth at positions x, as triangles: each grid cell clipped to the
/// outline (in the rest plane) and mapped bilinearly through its four corner particles; a
/// dropped corner is extrapolated linearly along a thread from kept particles (else across the
/// cell's diagonal). A flat cloth's surface is the outline exactly (area to rounding). With
/// `uv`, also each vertex's rest position in particle spacings (u along the weft, v along the
/// warp), one per vertex.
geometry::TriangleMesh cut_surface(const Grid& grid, const ClothCut& cut, const Positions& x, std::vector<Vec2>* uv = nullptr);

}  // namespace woven::model
