#include "woven/kes/curve.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>

#include "woven/common/error.hpp"

namespace woven::kes {

CurveFit::CurveFit(std::vector<Segment> segments, double data_max_x)
    : segments_(std::move(segments)), data_max_x_(data_max_x)
{
}

const Segment& CurveFit::segment_at(double x) const
{
    for (const Segment& s : segments_)
        if (x <= s.x_end) return s;
    return segments_.back();  // the line extrapolates
}

double CurveFit::value(double x) const
{
    if (x < 0) return -value(-x);
    return segment_at(x).value(x);
}

double CurveFit::slope(double x) const { return segment_at(std::abs(x)).slope(std::abs(x)); }

double CurveFit::curvature(double x) const
{
    const double c2 = 2.0 * segment_at(std::abs(x)).c2;
    return x < 0 ? -c2 : c2;
}

double CurveFit::secant(double x) const
{
    x = std::abs(x);
    const Segment& s = segment_at(x);
    if (&s == &segments_.front()) return s.c1 + s.c2 * x;  // c0 = 0: exact at the origin
    return s.value(x) / x;
}

double CurveFit::secant_derivative(double x) const
{
    // y' x - y = c2 x^2 - c0 on a segment y = c0 + c1 x + c2 x^2.
    const double ax = std::abs(x);
    const Segment& s = segment_at(ax);
    const double d = s.c0 == 0 ? s.c2 : s.c2 - s.c0 / (ax * ax);
    return x < 0 ? -d : d;
}

double CurveFit::integral(double x) const
{
    x = std::abs(x);
    double total = 0;
    for (const Segment& s : segments_) {
        const bool last = &s == &segments_.back();
        const double a = s.x_begin, b = last ? x : std::min(x, s.x_end);
        if (b > a) {
            auto prim = [&](double t) { return t * (s.c0 + t * (s.c1 / 2.0 + t * s.c2 / 3.0)); };
            total += prim(b) - prim(a);
        }
        if (x <= s.x_end) break;
    }
    return total;
}

namespace {

struct LineFit {
    double intercept, slope;
};

LineFit least_squares_line(const Curve& c, double from)
{
    double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (size_t k = 0; k < c.x.size(); ++k) {
        if (c.x[k] < from) continue;
        n += 1;
        sx += c.x[k];
        sy += c.y[k];
        sxx += c.x[k] * c.x[k];
        sxy += c.x[k] * c.y[k];
    }
    const double den = n * sxx - sx * sx;
    const double slope = (n * sxy - sx * sy) / den;
    return {(sy - slope * sx) / n, slope};
}

double max_error(const std::vector<Segment>& segs, const Curve& c)
{
    CurveFit f(segs, c.x.back());
    return max_fit_error(f, c);
}

double sum_squared_error(const std::vector<Segment>& segs, const Curve& c)
{
    CurveFit f(segs, c.x.back());
    double e = 0;
    for (size_t k = 0; k < c.x.size(); ++k) e += std::pow(f.value(c.x[k]) - c.y[k], 2);
    return e;
}

bool non_decreasing(const Segment& s)
{
    return s.slope(s.x_begin) >= 0 && s.slope(s.x_end) >= 0;
}

/// One quadratic y = c1 x + c2 x^2 on [0, xj] meeting the line in value and slope at xj.
std::vector<Segment> single_quadratic(const LineFit& L, double xj)
{
    // c1 xj + c2 xj^2 = a + b xj and c1 + 2 c2 xj = b  =>  c2 = -a/xj^2, c1 = b + 2a/xj.
    Segment q{0, xj, 0, L.slope + 2 * L.intercept / xj, -L.intercept / (xj * xj)};
    Segment line{xj, std::numeric_limits<double>::infinity(), L.intercept, L.slope, 0};
    return {q, line};
}

/// Two quadratics on [0, xm] and [xm, xj] then the line; the one free coefficient (the
/// curvature r of the middle segment) is chosen by least squares on the points below xj.
std::vector<Segment> double_quadratic(const LineFit& L, double xm, double xj, const Curve& c)
{
    const double yj = L.intercept + L.slope * xj;
    const double d = xm - xj;
    // Middle: y = yj + b (x - xj) + r (x - xj)^2. First: y = p1 x + p2 x^2 with C0/C1 at xm:
    //   p2 = (b xm + 2 r d xm - Y(xm)) / xm^2,   p1 = b + 2 r d - 2 p2 xm,   Y(xm) = yj + b d + r d^2.
    auto build = [&](double r) {
        const double ym = yj + L.slope * d + r * d * d;
        const double p2 = (L.slope * xm + 2 * r * d * xm - ym) / (xm * xm);
        const double p1 = L.slope + 2 * r * d - 2 * p2 * xm;
        Segment first{0, xm, 0, p1, p2};
        // middle in global coefficients: r x^2 + (b - 2 r xj) x + (yj - b xj + r xj^2)
        Segment middle{xm, xj, yj - L.slope * xj + r * xj * xj, L.slope - 2 * r * xj, r};
        Segment line{xj, std::numeric_limits<double>::infinity(), L.intercept, L.slope, 0};
        return std::vector<Segment>{first, middle, line};
    };
    // The fitted values are affine in r: y_k(r) = u_k + v_k r. Solve the 1-D least squares.
    const auto s0 = build(0.0), s1 = build(1.0);
    CurveFit f0(s0, c.x.back()), f1(s1, c.x.back());
    double num = 0, den = 0;
    for (size_t k = 0; k < c.x.size(); ++k) {
        if (c.x[k] > xj) continue;
        const double u = f0.value(c.x[k]), v = f1.value(c.x[k]) - u;
        num += v * (c.y[k] - u);
        den += v * v;
    }
    return build(den > 0 ? num / den : 0.0);
}

/// The many-segment fit: q quadratics on equal spans of [0, xj] and the line beyond, C1, through
/// the origin. Unknowns theta = (slope at 0, half the second derivative on each span); the
/// fitted values are linear in theta. Least squares on all points, subject to the KES slope
/// over [lo, hi] equalling `target` (Lagrange multiplier).
std::vector<Segment> constrained_spline(const Curve& c, int q, double xj, double lo, double hi, double target)
{
    const int m = q + 1;
    const double h = xj / q;
    auto build = [&](const Eigen::VectorXd& theta) {
        std::vector<Segment> segs;
        double y = 0, slope = theta[0];
        for (int k = 0; k < q; ++k) {
            const double t = k * h, ck = theta[1 + k];
            // local y + slope (x - t) + ck (x - t)^2 in global coefficients
            segs.push_back({t, k + 1 == q ? xj : (k + 1) * h, y - slope * t + ck * t * t, slope - 2 * ck * t, ck});
            y += slope * h + ck * h * h;
            slope += 2 * ck * h;
        }
        segs.front().c0 = 0;  // through the origin, exactly
        segs.push_back({xj, std::numeric_limits<double>::infinity(), y - slope * xj, slope, 0});
        return segs;
    };
    const int n = static_cast<int>(c.x.size());
    Eigen::MatrixXd A(n, m);
    Eigen::RowVectorXd C(m);
    for (int j = 0; j < m; ++j) {
        Eigen::VectorXd e = Eigen::VectorXd::Zero(m);
        e[j] = 1;
        const CurveFit f(build(e), c.x.back());
        for (int i = 0; i < n; ++i) A(i, j) = f.value(c.x[i]);
        C[j] = (f.value(hi) - f.value(lo)) / (hi - lo);
    }
    Eigen::VectorXd y(n);
    for (int i = 0; i < n; ++i) y[i] = c.y[i];
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(m + 1, m + 1);
    Eigen::VectorXd rhs(m + 1);
    K.topLeftCorner(m, m) = 2 * A.transpose() * A;
    K.topRightCorner(m, 1) = C.transpose();
    K.bottomLeftCorner(1, m) = C;
    rhs.head(m) = 2 * A.transpose() * y;
    rhs[m] = target;
    const Eigen::VectorXd sol = K.fullPivLu().solve(rhs);
    return build(sol.head(m));
}

double max_relative_error(const std::vector<Segment>& segs, const Curve& c, double from)
{
    const CurveFit f(segs, c.x.back());
    double e = 0;
    for (size_t k = 0; k < c.x.size(); ++k)
        if (c.x[k] >= from && c.y[k] > 0) e = std::max(e, std::abs(f.value(c.x[k]) - c.y[k]) / c.y[k]);
    return e;
}

}  // namespace

CurveFit fit_first_stage(const Curve& curve, const FitOptions& options, const std::string& what)
{
    const size_t n = curve.x.size();
    size_t outer = 0;
    for (double x : curve.x) outer += x >= options.line_from;
    if (n < 3 || outer < 2)
        throw InputError(what, "", "needs at least 3 points with at least 2 at or beyond " + std::to_string(options.line_from) + " to fit the outer line (Sec. 5.1)");
    const LineFit line = least_squares_line(curve, options.line_from);
    const double x_max = curve.x.back();

    // Junction candidates: a fine grid over (0, x_max]; the best single quadratic first.
    const int kCandidates = 200;
    std::vector<Segment> best;
    double best_sse = std::numeric_limits<double>::infinity();
    for (int k = 1; k <= kCandidates; ++k) {
        const double xj = x_max * k / kCandidates;
        auto segs = single_quadratic(line, xj);
        if (!non_decreasing(segs[0])) continue;
        const double sse = sum_squared_error(segs, curve);
        if (sse < best_sse) best_sse = sse, best = segs;
    }
    const double y_max = *std::max_element(curve.y.begin(), curve.y.end());
    const double target = data_slope(curve, options.slope_from, options.slope_to);
    const bool window_in_data = options.slope_to <= x_max && options.slope_from < options.slope_to;
    auto slope_ok = [&](const std::vector<Segment>& segs) {
        if (!window_in_data) return true;
        const double s = fit_slope(CurveFit(segs, x_max), options.slope_from, options.slope_to);
        return std::abs(s - target) <= options.slope_tolerance * std::abs(target);
    };
    // Additional segments (Sec. 5.1) when the paper's fit misses the KES slope.
    auto more_segments = [&](std::vector<Segment> fallback) {
        std::vector<Segment> chosen;
        double chosen_error = std::numeric_limits<double>::infinity();
        for (int q = 1; q <= options.max_segments; ++q) {
            auto segs = constrained_spline(curve, q, options.slope_to, options.slope_from, options.slope_to, target);
            bool monotone = true;
            for (const Segment& sg : segs) monotone = monotone && sg.slope(sg.x_begin) >= 0 && (std::isinf(sg.x_end) ? sg.c2 == 0 : sg.slope(sg.x_end) >= 0);
            if (!monotone) continue;
            const double err = max_relative_error(segs, curve, options.slope_from);
            if (err < chosen_error) chosen_error = err, chosen = segs;
            if (err <= options.relative_tolerance) break;
        }
        return chosen.empty() ? fallback : chosen;
    };
    if (!best.empty() && max_error(best, curve) <= options.single_segment_tolerance * y_max) {
        if (slope_ok(best)) return CurveFit(best, x_max);
        return CurveFit(more_segments(best), x_max);
    }

    // Two quadratic segments (Sec. 5.1: "additional segments", C0/C1 at each boundary).
    const int kCoarse = 60;
    for (int kj = 2; kj <= kCoarse; ++kj) {
        const double xj = x_max * kj / kCoarse;
        for (int km = 1; km < kj; ++km) {
            const double xm = x_max * km / kCoarse;
            auto segs = double_quadratic(line, xm, xj, curve);
            if (!non_decreasing(segs[0]) || !non_decreasing(segs[1])) continue;
            const double sse = sum_squared_error(segs, curve);
            if (sse < best_sse) best_sse = sse, best = segs;
        }
    }
    if (window_in_data && (best.empty() || !slope_ok(best))) best = more_segments(best);
    if (best.empty())
        throw InputError(what, "", "no non-decreasing piecewise quadratic/linear fit exists; is the curve a first-stage loading curve?");
    return CurveFit(best, x_max);
}

double fit_slope(const CurveFit& fit, double lo, double hi) { return (fit.value(hi) - fit.value(lo)) / (hi - lo); }

double data_slope(const Curve& c, double x_lo, double x_hi)
{
    auto interp = [&](double x) {
        if (x <= c.x.front()) return c.y.front();
        for (size_t k = 1; k < c.x.size(); ++k)
            if (x <= c.x[k]) {
                const double t = (x - c.x[k - 1]) / (c.x[k] - c.x[k - 1]);
                return c.y[k - 1] + t * (c.y[k] - c.y[k - 1]);
            }
        return c.y.back();
    };
    x_hi = std::min(x_hi, c.x.back());
    return (interp(x_hi) - interp(x_lo)) / (x_hi - x_lo);
}

double max_fit_error(const CurveFit& fit, const Curve& c)
{
    double e = 0;
    for (size_t k = 0; k < c.x.size(); ++k) e = std::max(e, std::abs(fit.value(c.x[k]) - c.y[k]));
    return e;
}

}  // namespace woven::kes
