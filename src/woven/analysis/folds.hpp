#pragma once
// Fold analysis of a drape over a box-like obstacle (the paper's cube, Sec. 6): horizontal
// sections of the cloth below the box's top face, and at each corner the billows that leave it.
//
//   seen from above (box frame, +z up, corners counter-clockwise from +x +y):
//
//        corner 1 (-x,+y) +---------+ corner 0 (+x,+y)
//                         |         |     /  diagonal: from the centre through the corner
//                         |   box   |    /   billow angle: from the diagonal to (peak - corner),
//                         |         |        counter-clockwise positive, degrees
//        corner 2 (-x,-y) +---------+ corner 3 (+x,-y)
//
// A billow is a local maximum, along a closed section, of the distance from the box's footprint
// whose topographic prominence is at least FoldOptions::prominence_m. The section is treated
// as a loop (no start): a billow that straddles the point where the loop happens to start is
// one billow. All lengths in m, angles in degrees.
#include <array>
#include <optional>
#include <vector>

#include "woven/common/types.hpp"
#include "woven/geometry/obstacle.hpp"
#include "woven/geometry/triangle_mesh.hpp"

namespace woven::analysis {

/// The obstacle's footprint: a rectangle (box frame rotated by `yaw_rad` about +z) and the
/// height of its top face.
struct BoxFootprint {
    Vec2 centre = Vec2::Zero();    ///< m, in the xy plane
    Vec2 half = Vec2(0.25, 0.25);  ///< half extents along the box's x and y axes (m), > 0
    double yaw_rad = 0;            ///< rotation about +z (rad)
    double top_z = 0.5;            ///< height of the top face (m)

    /// Box-frame coordinates of a world xy point.
    Vec2 to_local(const Vec2& p) const;
    /// World xy of a box-frame point.
    Vec2 to_world(const Vec2& q) const;
    /// Signed distance in the plane from the rectangle (m): > 0 outside, < 0 inside.
    double distance(const Vec2& p) const;
    /// World xy of corner c (0..3, see the sketch).
    Vec2 corner(int c) const;
    /// Unit outward diagonal direction of corner c (world).
    Vec2 diagonal(int c) const;
    /// The corner whose quadrant of the box frame holds p (0..3).
    int quadrant(const Vec2& p) const;
};

/// The footprint of the scene's box obstacle with the highest top face (the paper's cube, a
/// table top made of a box), or std::nullopt when the scene has no box.
std::optional<BoxFootprint> box_footprint(const geometry::ObstacleSet& obstacles);

/// Settings of the fold analysis.
struct FoldOptions {
    /// Depths of the sections below the top face (m), each > 0.
    std::vector<double> depths_m = {0.10, 0.20};
    /// Smallest topographic prominence of a billow (m): a maximum must rise this far above the
    /// lower of the two minima that separate it from higher ground on either side. 1 cm is half
    /// the paper's particle spacing: a fold smaller than that is not resolved by the grid.
    double prominence_m = 0.01;
};

/// A polyline in a horizontal plane (m).
struct Section {
    std::vector<Vec3> points;  ///< in order along the curve
    bool closed = false;       ///< the last point connects back to the first
};

/// The curves where the plane z = height cuts the mesh, each chained through shared edges:
/// closed loops and open arcs (ending at the mesh boundary). A vertex exactly at the height
/// counts as above it. Faces with an index out of range or non-finite vertices are skipped.
std::vector<Section> slice(const geometry::TriangleMesh& mesh, double height);

/// One billow.
struct Billow {
    int corner = 0;             ///< 0..3
    double angle_deg = 0;       ///< from the corner's diagonal to (peak - corner), counter-clockwise positive
    double standout_m = 0;      ///< distance of the peak from the footprint (m)
    double prominence_m = 0;    ///< its topographic prominence along the section (m)
    Vec3 point = Vec3::Zero();  ///< the peak (m)
};

/// The billows of one section: the maxima of footprint distance along it (a closed section is
/// treated as periodic, an open one as having ends) with prominence >= prominence_m, each
/// assigned to the corner whose quadrant holds it; sorted by corner, then angle.
std::vector<Billow> find_billows(const Section& section, const BoxFootprint& box, double prominence_m);

/// The section at one height.
struct SectionFolds {
    double depth_m = 0;           ///< below the top face (m)
    double height_m = 0;          ///< z of the section (m)
    bool found = false;           ///< a section surrounds the box at this height
    bool closed = false;          ///< ... and is a closed loop
    double length_m = 0;          ///< its length (m)
    std::vector<Billow> billows;  ///< all corners
    /// Billows of corner c.
    std::vector<Billow> at_corner(int c) const;
};

/// The drape's folds and its shape measures.
struct FoldAnalysis {
    std::vector<SectionFolds> sections;  ///< one per FoldOptions::depths_m, in that order
    Vec3 lowest_point = Vec3::Zero();    ///< lowest mesh vertex (m)
    /// Per side, +x, +y, -x, -y of the box frame: top_z minus the lowest z of the vertices
    /// in front of that side (outside the footprint, within the side's extent); 0 when none (m).
    std::array<double, 4> hanging_m{};
    double projected_area_m2 = 0;  ///< area of the union of the faces projected on the xy plane (m^2)
};

/// Sections the mesh at each depth below the box's top face, picks the section that surrounds
/// the footprint (the longest closed loop around the centre, else the longest open arc), finds
/// its billows, and measures the lowest point, the hanging length of each side and the
/// projected area (faces rasterised on a 1 mm grid). Throws InputError on a non-positive depth,
/// prominence or half extent, or an empty mesh.
FoldAnalysis analyse_folds(const geometry::TriangleMesh& cloth, const BoxFootprint& box, const FoldOptions& options = {});

/// What a corner's section shows (the paper's Sec. 6 and Fig. 8 name three): cotton's single
/// billow leaving the corner along its diagonal, wool's collapse into two folds, polyester/
/// cotton's fold pushed round the corner.
enum class CornerStructure {
    NONE,            ///< no fold leaves the corner
    SINGLE_BILLOW,   ///< one fold, within kDiagonalToleranceDeg of the diagonal (45 degrees to the sides)
    PUSHED_BILLOW,   ///< one fold further round the corner
    TWO_FOLDS,       ///< two folds
    SEVERAL_FOLDS,   ///< three or more
};

/// "none", "single billow", "pushed billow", "two folds", "several folds".
const char* to_string(CornerStructure s);

/// A billow this close to the corner's diagonal (degrees) leaves the corner "at 45 degrees".
inline constexpr double kDiagonalToleranceDeg = 15.0;

/// Billows further than this from the diagonal (deg) point back along a side more than they
/// continue it (45 deg is the side's line continued past the corner, 135 along the side): a wave
/// of the side's panel, not a fold leaving the corner. 90 is the bisector, and it falls in the
/// gap of every cube drape measured (docs/EXPERIMENTS.md, "Reading a corner"): corner folds
/// within 86 deg, side waves at 99-132 deg. (80 cut through the folds: the fast solver's
/// cotton folds at 81-84 deg stand out as far as their partners at 50-55 deg.)
inline constexpr double kCornerConeDeg = 90;

/// A billow in the cone that stands out less than this fraction of the corner's largest is a
/// ripple on the flank of the corner's fold, not a fold of its own: a person counting the folds
/// of the paper's Fig. 8 counts lobes of cloth of the same order as their neighbour, not the
/// small waves on one lobe's flank (docs/EXPERIMENTS.md, "Reading a corner").
inline constexpr double kFoldStandoutFraction = 0.5;

/// The billows of one corner split as a person reads them (the rule of kCornerConeDeg and
/// kFoldStandoutFraction): the folds leaving the corner, the smaller ripples in the cone and the
/// waves of the side panels beyond it; each in the input's order.
struct CornerBillows {
    std::vector<Billow> folds;
    std::vector<Billow> ripples;
    std::vector<Billow> side_waves;
};
CornerBillows split_corner_billows(const std::vector<Billow>& billows);

/// The structure of one corner's billows (one section's, Billow::corner all the same): that of
/// the folds of split_corner_billows.
CornerStructure corner_structure(const std::vector<Billow>& billows);

/// The corner's asymmetry (degrees): the standout-weighted mean of its billows' angles from the
/// diagonal; 0 for none, for a billow on the diagonal and for two folds placed symmetrically.
double corner_asymmetry_deg(const std::vector<Billow>& billows);

/// Area of the union of the mesh's faces projected on the xy plane (m^2), by counting the
/// centres of `cell_m` square cells covered by some face.
double projected_area(const geometry::TriangleMesh& mesh, double cell_m = 1e-3);

}  // namespace woven::analysis
