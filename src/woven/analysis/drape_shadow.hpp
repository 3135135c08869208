#pragma once
// The Cusick drape test's measures (BS 5058, ISO 9073-9): the shadow of a draped specimen (its
// vertical projection), the drape coefficient, and the nodes (folds) read from the shadow's
// outline.
//
//   seen from above (+z up); angles from the warp direction (grid v, +y) towards the weft (+x):
//
//                  0 deg: warp (+y)
//                        ^
//             ,-~~~~~~~~-|-~~~~~~~~-,     specimen, flat radius R
//           /      ,-----+-----,      \     (the node tips reach out, the
//   270 deg |------|  disc r_d |------|--> 90 deg: weft (+x)
//           \      '-----+-----'      /     troughs between them in)
//             '-~~~~~~~~-+-~~~~~~~~-'     r(theta): distance from the disc's centre to the
//                                         shadow's outer edge along the ray at theta
//
//   DC = (A_shadow - A_disc) / (A_specimen - A_disc) x 100 %
//
// A node is a lobe of the shadow: a maximum of r(theta), treated as periodic (a lobe that
// straddles theta = 0 is one lobe), whose topographic prominence is at least a threshold.
// Lengths in m, areas in m^2, angles in degrees.
#include <cstddef>
#include <vector>

#include "woven/analysis/peaks.hpp"
#include "woven/common/types.hpp"
#include "woven/geometry/triangle_mesh.hpp"

namespace woven::analysis {

/// Caps of the shadow measurement, whatever the mesh (a start file with one particle 1000 km
/// away made the scanline table 9.3 GB at 1 km): at most kMaxShadowRows scanlines and at most
/// kMaxShadowRowSpans face-row crossings (the time); beyond either the scanlines are set wider
/// (shadow_row_m). Memory is then O(faces), shadow_memory_bytes, never O(extent / row).
inline constexpr long long kMaxShadowRows = 1LL << 20;
inline constexpr long long kMaxShadowRowSpans = 1LL << 26;
/// The caps shadow_area applies: the defaults above; smaller ones (a fuzz harness's, which
/// needs each input quick) widen the rows sooner. Each at least 1.
struct ShadowCaps {
    long long rows = kMaxShadowRows;
    long long row_spans = kMaxShadowRowSpans;
};

/// Largest raster of rasterize_shadow (pixels): 64 MiB.
inline constexpr long long kMaxShadowPixels = 1LL << 26;

/// The scanline spacing shadow_area uses for `mesh` asked for `row_m` (m): row_m, or wider
/// where the caps above demand it (a standard specimen at 0.1 mm is far below them: 3,000
/// rows, some 2e5 crossings at a 0.5 cm spacing). Throws InputError if row_m <= 0 or a cap < 1.
double shadow_row_m(const geometry::TriangleMesh& mesh, double row_m = 1e-4, const ShadowCaps& caps = {});

/// Estimate of the memory shadow_area, rasterize_shadow (besides its pixels) and shadow_radius
/// (besides its n radii and n ray directions) use for `mesh` (bytes): about 120 bytes a face.
std::size_t shadow_memory_bytes(const geometry::TriangleMesh& mesh);

/// Area of the union of the mesh's faces projected on the xy plane (m^2). Scanlines
/// `row_m` apart (midpoint rule in y); along each the covered length is exact (the union of the
/// faces' x-intervals). The error is second order in `row_m` (the midpoint rule errs only in
/// the rows holding a vertex where the boundary's slope dx/dy jumps): measured 2e-6 relative,
/// 3e-4 percentage points of drape coefficient, for a 30 cm 720-gon at the default 0.1 mm
/// (tests/analysis/test_drape_shadow.cpp). Faces with non-finite vertices are skipped. The
/// spacing is shadow_row_m(mesh, row_m, caps). Throws InputError if row_m <= 0 or a cap < 1.
double shadow_area(const geometry::TriangleMesh& mesh, double row_m = 1e-4, const ShadowCaps& caps = {});

/// A black-and-white raster of the shadow: pixel (c, r) covers
/// [origin.x + c p, origin.x + (c+1) p] x [origin.y + r p, origin.y + (r+1) p], p = pixel_m;
/// it is 1 when its centre lies in the shadow. Row 0 is the lowest y.
struct ShadowRaster {
    int width = 0, height = 0;
    double pixel_m = 0;
    Vec2 origin = Vec2::Zero();
    std::vector<unsigned char> covered;  ///< width * height, index c + width * r
    double area_m2() const;              ///< covered pixels times pixel area (m^2)
};

/// Rasterises the projected faces on `width x height` pixels of side `pixel_m` from `origin`.
/// Throws InputError on a non-positive size or more than kMaxShadowPixels pixels.
ShadowRaster rasterize_shadow(const geometry::TriangleMesh& mesh, const Vec2& origin, double pixel_m, int width, int height);

/// The distance r(theta_k) from `centre` of the farthest point of the projected faces along
/// the ray at theta_k = 360 k / n degrees from +y towards +x (k = 0..n-1): the outer edge of the
/// shadow as a function of angle (re-entrant parts behind it are ignored). 0 where no face
/// meets the ray. Throws InputError if n < 8.
std::vector<double> shadow_radius(const geometry::TriangleMesh& mesh, const Vec2& centre, int n = 1440);

/// The drape coefficient DC = (A_shadow - A_disc) / (A_specimen - A_disc) x 100 (%). Throws
/// InputError unless 0 < A_disc < A_specimen.
double drape_coefficient_percent(double shadow_area_m2, double disc_area_m2, double specimen_area_m2);

/// The nodes of a drape.
struct Nodes {
    std::vector<double> angle_deg;    ///< of each node's tip, from the warp (+y) towards the weft (+x), in [0, 360), ascending
    std::vector<double> radius_m;     ///< r(theta) at the tip
    std::vector<double> depth_m;      ///< flat radius minus the tip's radius: how far the node reaches in from the specimen's edge
    std::vector<double> amplitude_m;  ///< prominence of the tip over the troughs beside it
    int count() const { return static_cast<int>(angle_deg.size()); }
};

/// Nodes from r(theta) (shadow_radius's sampling): its periodic peaks with prominence >=
/// min_prominence_m. Throws InputError as periodic_peaks does.
Nodes find_nodes(const std::vector<double>& radius_m, double flat_radius_m, double min_prominence_m);

/// Everything the drape test reads from a draped specimen.
struct DrapeShadow {
    double shadow_area_m2 = 0;
    double disc_area_m2 = 0;
    double specimen_area_m2 = 0;
    double drape_coefficient_percent = 0;
    std::vector<double> radius_m;  ///< r(theta), shadow_radius's sampling
    Nodes nodes;
};

/// Settings of measure_drape.
struct DrapeShadowOptions {
    double row_m = 1e-4;  ///< scanline spacing of the area (m)
    int angles = 1440;    ///< samples of r(theta) (0.25 degree)
    /// Smallest prominence of a node as a fraction of the overhang (specimen radius minus disc
    /// radius): 0.1 is 6 mm for the standard 30 cm specimen on an 18 cm disc, several times the
    /// shadow's faceting at a 1 cm spacing and well below a real node's 2-4 cm.
    double min_prominence_fraction = 0.1;
};

/// The shadow, the drape coefficient and the nodes of a draped specimen (its surface as a
/// triangle mesh) centred at `centre` on a disc of radius disc_radius_m; the specimen's flat
/// area and radius are given (the area the model's masses stand for). Throws InputError on
/// inconsistent sizes.
DrapeShadow measure_drape(const geometry::TriangleMesh& specimen, const Vec2& centre, double disc_radius_m, double specimen_radius_m,
                          double specimen_area_m2, const DrapeShadowOptions& options = {});

}  // namespace woven::analysis
