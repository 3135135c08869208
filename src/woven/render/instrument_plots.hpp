#pragma once
// The instruments' and experiments' plots and pictures: KES curves and loops, a curve's fit,
// the Cusick shadow and the corner map, drawn from their numbers (the jobs in app/ compute them).
#include <string>
#include <vector>

#include "woven/common/types.hpp"
#include "woven/render/image.hpp"
#include "woven/render/plot.hpp"

namespace woven::render {

/// tab10's first colours (sRGB): the plots' input (data) in blue and green, simulated in orange and red.
inline const Vec3 kBlue(0.122, 0.467, 0.706), kOrange(1.000, 0.498, 0.055), kGreen(0.173, 0.627, 0.173), kRed(0.839, 0.153, 0.157);

/// One direction of a KES test: the simulated curve (x, y) and the input (input_x, input_y).
struct KesCurveView {
    std::string direction;  ///< "warp" or "weft"
    std::vector<double> x, y, input_x, input_y;
};

/// A loop plot: each distinct input once as a line, each simulated run as dots. `page` (the
/// report's style): "input DIRECTION" in blue (warp) or green (weft), simulated in orange or
/// red, a lone input labelled "input"; else (kes-test's) "input loop DIRECTION" in tab10's
/// cycle, "input loop" when one input serves two runs.
Plot kes_loop_plot(const std::string& title, const std::string& x_label, const std::string& y_label, const std::vector<KesCurveView>& runs,
                   bool page);

/// A curve plot: each run's input as dots ("input DIRECTION" when `per_direction`, else the first
/// run's alone, "input curve") and its simulated curve as a line with dots.
Plot kes_curve_plot(const std::string& title, const std::string& x_label, const std::string& y_label, const std::vector<KesCurveView>& runs,
                    bool per_direction);

/// A KES curve (dark grey dots), its fit (a line in `fit_colour`) and the fit's segment
/// junctions (red dots; none when empty).
struct CurveFitView {
    std::string title, x_label, y_label;
    std::vector<double> data_x, data_y, fit_x, fit_y, junction_x, junction_y;
    Vec3 fit_colour;
};
Plot curve_fit_plot(const CurveFitView& c);

/// Half the side of the square shadow_picture shows, m, for a specimen of radius R.
inline double shadow_half_width(double specimen_radius) { return 1.08 * specimen_radius; }

/// The Cusick shadow.png: `covered` (pixels x pixels, index column + pixels * row, row 0 at the
/// bottom, over the square of shadow_half_width about the centre) in black on white, seen from
/// above with the warp (+y) up and the weft (+x) right; the specimen (grey) and disc (blue)
/// circles, dotted axes, a red tick from each node's radius outwards (angles from the warp), and
/// "DC x %, n nodes".
Image shadow_picture(const std::vector<unsigned char>& covered, int pixels, double specimen_radius, double disc_radius,
                     const std::vector<double>& node_angle_deg, const std::vector<double>& node_radius_m, double dc_percent);

/// One cell of the corner map.
struct MapCellView {
    int structure = 0;  ///< index into the map's structures
    double mean_billows = 0, mean_abs_angle_deg = 0;  ///< angle 0: not written
    bool converged = false;
};
/// A fabric marked on the map at its bending length and warp/weft ratio.
struct MapMark {
    std::string name;
    double length_cm = 0, ratio = 1;
    Vec3 colour;  ///< its dot's sRGB
};
/// corner_map.png: `cells` row by row (ratios[r], lengths[c]; ratio upwards, length rightwards)
/// coloured by structure (green, orange, blue, grey in the order of `structures`, which names
/// them in the legend), the marks placed linearly in length and log2(ratio) with their names
/// where they cover no text, and `footer` at the bottom.
Image corner_map_picture(const std::vector<MapCellView>& cells, const std::vector<double>& ratios, const std::vector<double>& lengths,
                         const std::vector<MapMark>& marks, const std::vector<std::string>& structures, const std::string& footer);

}  // namespace woven::render
