#pragma once
// A garment's pattern pieces on one thread grid (docs/GARMENT-FORMAT.md). Each piece is an
// outline of straight and circular-arc segments in its own plane (m), turned by its grain angle
// on the fabric and cut from the grid as the Cusick specimen is (outline.hpp: the particles
// inside, each weighing W x its share of the outline's area). The pieces lie side by side on
// the grid with inactive particles between them, so that no stencil joins two pieces: only the
// seams do (seams.hpp).
//
//     grid (warp along v = y, weft along u = x):
//       . . . . . . . . . . . . . .
//       . o o o o . . . . o o o o .        piece k's point P (its own frame) sits at
//       . o o o o . . . . o o o o .        R(-grain_k) P + offset_k on the grid
//       . o o o o . . . . o o o o .
//       . . . . . . . . . . . . . .
//
// A piece is placed around the body by wrapping its plane on a cone or a cylinder about the
// body's vertical axis (x = y = 0), an isometry, so the cloth starts unstrained (Placement).
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "woven/common/types.hpp"
#include "woven/model/grid.hpp"
#include "woven/model/outline.hpp"
#include "woven/model/seams.hpp"

namespace woven::model {

/// One segment of a piece's outline, from `a` to `b` (m, the piece's frame): straight, or a
/// circular arc about `centre` (|a - centre| = |b - centre|) turning counter-clockwise (`ccw`)
/// or clockwise, less than a full turn.
struct OutlineSegment {
    std::string name;
    Vec2 a = Vec2::Zero(), b = Vec2::Zero();
    std::optional<Vec2> centre;  ///< an arc's centre; absent: straight
    bool ccw = true;
    enum class Role { EDGE, WAIST, HEM };
    Role role = Role::EDGE;  ///< WAIST: held where it starts (the waistband); HEM: the hem measured

    double radius() const { return centre ? (a - *centre).norm() : 0.0; }
    /// The arc's signed turn (rad, > 0 counter-clockwise), 0 for a straight segment.
    double turn() const;
    double length() const;
    /// The point at arc length s from a (m).
    Vec2 point(double s) const;
    /// The arc length (clamped to [0, length]) of the segment's point nearest p, and its distance.
    double project(const Vec2& p, double* distance) const;
};

/// How a piece is wrapped around the body's axis (z up, the axis x = y = 0), seen from outside:
/// the piece's `down` direction (in its plane) runs down the body at azimuth `azimuth`, its
/// right-hand side towards increasing azimuth.
///   CONE: `origin` is the apex (the centre of the waist and hem arcs), at height `height`; a
///     point at distance rho from it and angle psi from `down` goes to radius rho sin(alpha),
///     height `height` - rho cos(alpha), azimuth `azimuth` + psi / sin(alpha) (alpha the half
///     angle; 90 degrees: a flat ring, a circular skirt before it falls).
///   CYLINDER: `origin` goes to radius `radius`, height `height`, azimuth `azimuth`; a point
///     across by u and down by v from it, to azimuth + u / radius and height - v.
struct Placement {
    enum class Wrap { CONE, CYLINDER };
    Wrap wrap = Wrap::CYLINDER;
    Vec2 origin = Vec2::Zero();              ///< m, the piece's frame
    double down = -0.5 * 3.141592653589793;  ///< rad: the direction down the body, in the piece's frame (default -y)
    double azimuth = 0;                      ///< rad, from +x towards +y
    double height = 0;                       ///< m
    double half_angle = 0;                   ///< rad (CONE), in (0, pi/2]
    double radius = 0;                       ///< m (CYLINDER)
};

/// The position of the piece's point p around the body (m).
Vec3 place_point(const Placement& placement, const Vec2& p);

struct PatternPiece {
    std::string name;
    std::vector<OutlineSegment> segments;  ///< in order, each starting where the last ended, closed
    double grain = 0;                      ///< rad between the warp and the piece's y axis (its grain line)
    Placement placement;
};

/// Two segments sewn together: a's start to b's start (b's end when `reversed`), joined along
/// their lengths by arc length (as fractions of each segment's length).
struct PatternSeam {
    int piece_a = 0, segment_a = 0, piece_b = 0, segment_b = 0;
    bool reversed = false;
    std::string name;
};

struct Pattern {
    std::vector<PatternPiece> pieces;
    std::vector<PatternSeam> seams;
};

/// The particles of one segment's cut edge, by arc length, and each one's point on the outline
/// as seams.hpp extrapolates it: sum_k c[k] x[ids[k]] (the particle, its inward weft and warp
/// neighbours).
struct EdgeParticles {
    std::vector<int> particles;  ///< ascending arc length
    std::vector<double> s;       ///< arc length from the segment's start (m), one per particle
    std::vector<std::array<int, 3>> ids;
    std::vector<std::array<double, 3>> c;
};

/// The pattern cut from one grid at spacing sigma, sewn and placed.
struct GarmentCloth {
    Grid grid;
    std::vector<ClothCut> cuts;                     ///< per piece: its cut of the grid (active: its particles only)
    std::vector<char> active;                       ///< per particle: in some piece
    std::vector<double> area;                       ///< per particle (m^2)
    std::vector<int> piece_of;                      ///< per particle: its piece, -1 between pieces
    std::vector<Vec2> piece_point;                  ///< per particle: its rest position in its piece's frame (m)
    std::vector<std::vector<EdgeParticles>> edges;  ///< [piece][segment]
    SeamSet seams;                                  ///< the stitches of every seam (Stitch::seam: the seam's index)
    Positions start;                                ///< every particle placed around the body (inactive ones too)
    std::vector<int> waist;                         ///< the particles of WAIST segments (held), ascending
    std::vector<int> hem;                           ///< the particles of HEM segments, ascending
};

/// The closed polygon of a piece's outline (arcs as chords of at most kCircleSegments per turn).
Ring piece_ring(const PatternPiece& piece);

/// Cuts the pattern from a grid of spacing sigma (m), finds each segment's edge particles,
/// sews the seams and places every particle. InputError(source, "piece[k]" ...) where a piece's
/// outline is not closed or not simple, or too small for the spacing; (source, "seam[k]" ...)
/// where a seam's edge holds no particle.
GarmentCloth cut_pattern(const Pattern& pattern, double sigma, const std::string& source);

}  // namespace woven::model
