#pragma once
// Kawabata first-stage loading curves and their piecewise polynomial fit (paper Sec. 5.1).
#include <string>
#include <vector>

namespace woven::kes {

/// A first-stage loading curve (from zero to the positive maximum; paper Sec. 5.1).
/// Bending (KES-FB2): x = curvature K (1/cm), y = moment M (gf.cm/cm).
/// Shear (KES-FB1): x = shear angle (degrees), y = force F (gf/cm).
struct Curve {
    std::vector<double> x;  ///< abscissae, strictly increasing, >= 0
    std::vector<double> y;  ///< ordinates, non-decreasing
};

/// One polynomial piece y = c0 + c1 x + c2 x^2 on [x_begin, x_end] (x in the curve's units).
struct Segment {
    double x_begin = 0, x_end = 0;
    double c0 = 0, c1 = 0, c2 = 0;
    double value(double x) const { return c0 + x * (c1 + x * c2); }
    double slope(double x) const { return c1 + 2.0 * c2 * x; }
};

/// Options of the Sec. 5.1 fit.
struct FitOptions {
    /// The outer, stable part of the curve starts here (curve units): the line is fitted by
    /// least squares to the points with x >= line_from. KES uses 0.5 1/cm for B, 0.5 deg for G.
    double line_from = 0.5;
    /// Accept a single quadratic from the origin when its largest error to the data is below
    /// this fraction of the largest ordinate; otherwise use two quadratic segments.
    double single_segment_tolerance = 0.02;
    /// The KES slope window (B: 0.5-1.5 1/cm, G: 0.5-5 degrees). The fit's own slope over it,
    /// (y(slope_to) - y(slope_from)) / (slope_to - slope_from), must equal the data's
    /// (data_slope) within slope_tolerance (relative); when the line-and-quadratics fit above
    /// misses it (a curve still bending inside the window), more segments are used.
    double slope_from = 0.5, slope_to = 1.5;
    double slope_tolerance = 1e-4;
    /// The many-segment fit: quadratic segments on equal spans of [0, slope_to], then the line;
    /// as few as give every data point at or beyond slope_from within relative_tolerance of
    /// its value, at most max_segments.
    double relative_tolerance = 0.005;
    int max_segments = 8;
};

/// The fitted first-stage curve: quadratic segment(s) from the origin (through it, no slope
/// condition there), then the line fitted to the outer part; C0 and C1 at every junction.
/// Past the last segment the line continues (linear extrapolation); for x < 0 the curve is odd.
class CurveFit {
public:
    CurveFit() = default;
    explicit CurveFit(std::vector<Segment> segments, double data_max_x);

    /// y(x).
    double value(double x) const;
    /// dy/dx.
    double slope(double x) const;
    /// d2y/dx2 (piecewise constant).
    double curvature(double x) const;
    /// y(x)/x, exact near 0 (the first segment passes through the origin); slope(0) at x = 0.
    double secant(double x) const;
    /// d/dx (y/x) = (y' x - y) / x^2, exact near 0 (equal to c2 on the first segment).
    double secant_derivative(double x) const;
    /// Integral of y from 0 to x (x >= 0).
    double integral(double x) const;

    const std::vector<Segment>& segments() const { return segments_; }
    /// The outer line (the last segment).
    const Segment& line() const { return segments_.back(); }
    /// Largest abscissa of the data the fit was made from.
    double data_max_x() const { return data_max_x_; }

private:
    const Segment& segment_at(double x) const;
    std::vector<Segment> segments_;
    double data_max_x_ = 0;
};

/// Fits a first-stage curve as the paper's Sec. 5.1 says: the outer line by least squares,
/// then one or two quadratics from the origin meeting it in value and slope. When that fit's
/// KES slope misses the data's (options.slope_tolerance), "additional segments" (Sec. 5.1) by
/// the same rule: k quadratics on equal spans of [0, slope_to], C0 and C1 at every junction,
/// through the origin, then the line on [slope_to, inf), all fitted together by least squares
/// subject to the fit's KES slope equalling the data's exactly; k the fewest that meet
/// options.relative_tolerance (and stay non-decreasing). `what` names the curve in errors.
/// Throws InputError when the curve cannot be fitted (too few points in the outer part).
CurveFit fit_first_stage(const Curve& curve, const FitOptions& options, const std::string& what);

/// The fit's own KES slope over [lo, hi]: (value(hi) - value(lo)) / (hi - lo).
double fit_slope(const CurveFit& fit, double lo, double hi);

/// Least-squares slope of the data between x_lo and x_hi (KES: B between 0.5 and 1.5 1/cm,
/// G between 0.5 and 5 degrees), interpolating the curve at the ends.
double data_slope(const Curve& curve, double x_lo, double x_hi);

/// Largest |fit - data| over the data points.
double max_fit_error(const CurveFit& fit, const Curve& curve);

}  // namespace woven::kes
