#include "woven/render/plot.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <cairo-svg.h>
#include <cairo.h>

#include "woven/common/error.hpp"
#include "woven/render/text.hpp"

namespace woven::render {

namespace detail {

void set_font(cairo_t* cr, double size_px, bool bold)
{
    cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, size_px);
    // Unhinted metrics: text measures the same on every surface, so plot_frame's layout is the drawn one.
    cairo_font_options_t* o = cairo_font_options_create();
    cairo_font_options_set_hint_metrics(o, CAIRO_HINT_METRICS_OFF);
    cairo_font_options_set_hint_style(o, CAIRO_HINT_STYLE_NONE);
    cairo_set_font_options(cr, o);
    cairo_font_options_destroy(o);
}

}  // namespace detail

namespace {

constexpr double kTitleSize = 15, kLabelSize = 13, kTickSize = 12, kLegendSize = 12;

const std::array<Vec3, 10> kTab10 = {
    Vec3(0.122, 0.467, 0.706), Vec3(1.000, 0.498, 0.055), Vec3(0.173, 0.627, 0.173), Vec3(0.839, 0.153, 0.157),
    Vec3(0.580, 0.404, 0.741), Vec3(0.549, 0.337, 0.294), Vec3(0.890, 0.467, 0.761), Vec3(0.498, 0.498, 0.498),
    Vec3(0.737, 0.741, 0.133), Vec3(0.090, 0.745, 0.812)};

struct Axis {
    double lo = 0, hi = 1, step = 0.2;
    std::vector<double> ticks;
};

double nice_step(double raw)
{
    if (!(raw > 0) || !std::isfinite(raw)) return 1;
    const double mag = std::pow(10.0, std::floor(std::log10(raw)));
    const double f = raw / mag;
    return (f < 1.5 ? 1 : f < 3 ? 2 : f < 7 ? 5 : 10) * mag;
}

/// Axis over [lo, hi] of the finite data with a 5 % margin, ticks at multiples of a 1-2-5 step.
Axis make_axis(double lo, double hi, int target_ticks)
{
    Axis a;
    if (!(std::isfinite(lo) && std::isfinite(hi)) || lo > hi) {
        lo = 0;
        hi = 1;
    } else if (!std::isfinite(hi - lo)) {
        lo = -1e300;
        hi = 1e300;
    } else if (hi - lo <= std::max(std::abs(lo), std::abs(hi)) * 1e-12) {
        const double pad = lo == 0 ? 0.5 : 0.05 * std::abs(lo);
        lo -= pad;
        hi += pad;
    } else {
        const double m = 0.05 * (hi - lo);
        lo -= m;
        hi += m;
    }
    a.lo = lo;
    a.hi = hi;
    a.step = nice_step((hi - lo) / target_ticks);
    const double first = std::ceil(lo / a.step - 1e-9);
    for (int i = 0; i < 100; ++i) {
        const double t = (first + i) * a.step;
        if (t > hi + a.step * 1e-9) break;
        a.ticks.push_back(std::abs(t) < a.step * 1e-9 ? 0.0 : t);
    }
    return a;
}

std::string tick_label(double v, double step)
{
    char buf[64];
    const double big = std::max(std::abs(v), step);
    if (big >= 1e6 || step < 1e-4)
        std::snprintf(buf, sizeof buf, "%.3g", v);
    else {
        const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
        std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    }
    std::string s = buf;
    if (s.find_first_not_of("-0.") == std::string::npos && s[0] == '-') s.erase(0, 1);  // "-0" -> "0"
    return s;
}

/// Liang-Barsky clip of a segment to [x0, x1] x [y0, y1]; false when fully outside.
bool clip(double& ax, double& ay, double& bx, double& by, double x0, double x1, double y0, double y1)
{
    double t0 = 0, t1 = 1;
    const double dx = bx - ax, dy = by - ay;
    const double p[4] = {-dx, dx, -dy, dy};
    const double q[4] = {ax - x0, x1 - ax, ay - y0, y1 - ay};
    for (int i = 0; i < 4; ++i) {
        if (p[i] == 0) {
            if (q[i] < 0) return false;
            continue;
        }
        const double r = q[i] / p[i];
        if (p[i] < 0)
            t0 = std::max(t0, r);
        else
            t1 = std::min(t1, r);
        if (t0 > t1) return false;
    }
    const double nax = ax + t0 * dx, nay = ay + t0 * dy;
    bx = ax + t1 * dx;
    by = ay + t1 * dy;
    ax = nax;
    ay = nay;
    return std::isfinite(ax) && std::isfinite(ay) && std::isfinite(bx) && std::isfinite(by);
}

bool finite_pair(const Series& s, std::size_t k) { return std::isfinite(s.x[k]) && std::isfinite(s.y[k]); }
std::size_t count(const Series& s) { return std::min(s.x.size(), s.y.size()); }
double err_at(const Series& s, std::size_t k) { return k < s.err.size() && std::isfinite(s.err[k]) && s.err[k] > 0 ? s.err[k] : 0.0; }
bool has_line(const Series& s) { return s.style != Series::Style::POINTS; }
bool has_points(const Series& s) { return s.style != Series::Style::LINE; }

void font(cairo_t* cr, double size, bool bold = false) { detail::set_font(cr, size, bold); }

double text_width(cairo_t* cr, const std::string& s)
{
    cairo_text_extents_t e;
    cairo_text_extents(cr, s.c_str(), &e);
    return e.x_advance;
}

void color(cairo_t* cr, const Vec3& c, double a = 1) { cairo_set_source_rgba(cr, c[0], c[1], c[2], a); }

/// Text with its baseline's start at (x, y), anchored at 0 (left), 0.5 (centre) or 1 (right).
void text(cairo_t* cr, const std::string& s, double x, double y, double anchor = 0)
{
    cairo_move_to(cr, x - anchor * text_width(cr, s), y);
    cairo_show_text(cr, s.c_str());
}

struct Layout {
    PlotFrame f;
    Axis ax, ay;
    double legend_row = 18;
    double legend_covers = 0;  ///< samples of the data under the legend (inside the axes)
};

/// The legend's natural size: its widest label and its rows.
std::array<double, 2> legend_size(cairo_t* cr, const Plot& plot, double row)
{
    font(cr, kLegendSize);
    double text_w = 0;
    int rows = 0;
    for (const auto& s : plot.series)
        if (!s.label.empty()) {
            text_w = std::max(text_w, text_width(cr, s.label));
            ++rows;
        }
    if (rows == 0) return {0, 0};
    return {8 + 26 + 6 + text_w + 8, 16 + rows * row - 4};
}

/// Axes from the data, margins from the text; the legend inside the axes, in the corner with the
/// least data under it, or (`outside`) right of the axes.
Layout layout_with(cairo_t* cr, const Plot& plot, int W, int H, bool outside)
{
    Layout L;
    double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
    for (const auto& s : plot.series)
        for (std::size_t k = 0; k < count(s); ++k) {
            if (!finite_pair(s, k)) continue;
            const double e = err_at(s, k);
            if (plot.y_max && s.y[k] - e > *plot.y_max) continue;
            x0 = std::min(x0, s.x[k]);
            x1 = std::max(x1, s.x[k]);
            y0 = std::min(y0, s.y[k] - e);
            y1 = std::max(y1, plot.y_max ? std::min(s.y[k] + e, *plot.y_max) : s.y[k] + e);
        }
    L.ax = make_axis(x0, x1, std::max(3, W / 110));
    L.ay = make_axis(y0, y1, std::max(3, H / 80));
    if (plot.y_max && *plot.y_max > L.ay.lo && L.ay.hi > *plot.y_max) {
        L.ay.hi = *plot.y_max;
        while (!L.ay.ticks.empty() && L.ay.ticks.back() > L.ay.hi + 1e-12 * L.ay.step) L.ay.ticks.pop_back();
    }
    font(cr, kTickSize);
    double tick_w = 0;
    for (double t : L.ay.ticks) tick_w = std::max(tick_w, text_width(cr, tick_label(t, L.ay.step)));
    const double top = plot.title.empty() ? 14 : 36;
    const double left = 12 + (plot.y_label.empty() ? 0 : kLabelSize + 8) + tick_w + 6;
    const double bottom = H - (10 + kTickSize + 8 + (plot.x_label.empty() ? 0 : kLabelSize + 8));
    double right = W - 16.0 - 0.5 * text_width(cr, tick_label(L.ax.ticks.empty() ? 0 : L.ax.ticks.back(), L.ax.step)) + 8;
    const std::array<double, 2> legend = legend_size(cr, plot, L.legend_row);
    if (outside) right = std::min<double>(right, W - 16) - legend[0] - 10;
    PlotFrame& f = L.f;
    f.left = std::round(left) + 0.5;
    f.top = std::round(top) + 0.5;
    f.right = std::max(f.left + 10, std::round(std::min<double>(right, W - 16)) + 0.5);
    f.bottom = std::max(f.top + 10, std::round(bottom) + 0.5);
    if (plot.equal_aspect) {
        // Pixels per unit along each axis; the denser one is widened to match the other.
        const double aw = f.right - f.left, ah = f.bottom - f.top;
        const double sx = aw / (L.ax.hi - L.ax.lo), sy = ah / (L.ay.hi - L.ay.lo);
        Axis& a = sx > sy ? L.ax : L.ay;
        const double half = 0.5 * (sx > sy ? aw / sy : ah / sx), mid = 0.5 * (a.lo + a.hi);
        if (std::isfinite(half) && half > 0) {
            a.lo = mid - half;
            a.hi = mid + half;
            a.ticks.clear();
            const double first = std::ceil(a.lo / a.step - 1e-9);
            for (int i = 0; i < 200; ++i) {
                const double t = (first + i) * a.step;
                if (t > a.hi + a.step * 1e-9) break;
                a.ticks.push_back(std::abs(t) < a.step * 1e-9 ? 0.0 : t);
            }
        }
    }
    f.x_lo = L.ax.lo;
    f.x_hi = L.ax.hi;
    f.y_lo = L.ay.lo;
    f.y_hi = L.ay.hi;
    for (std::size_t si = 0; si < plot.series.size(); ++si) {
        f.colors.push_back(plot.series[si].color.value_or(kTab10[si % kTab10.size()]));
    }
    if (legend[0] == 0) return L;
    const double aw = f.right - f.left, ah = f.bottom - f.top;
    if (outside) {
        f.legend_w = std::min(legend[0], W - 2 - (f.right + 10));
        f.legend_h = std::min(legend[1], H - 2 - f.top);
        f.legend_x = f.right + 10;
        f.legend_y = f.top;
        return L;
    }
    // The corner whose box covers the fewest samples of the drawn data.
    f.legend_w = std::min(aw - 8, legend[0]);
    f.legend_h = std::min(ah - 8, legend[1]);
    const auto X = [&](double x) { return f.left + (x - f.x_lo) / (f.x_hi - f.x_lo) * aw; };
    const auto Y = [&](double y) { return f.bottom - (y - f.y_lo) / (f.y_hi - f.y_lo) * ah; };
    const double m = 6;
    const std::array<std::array<double, 2>, 4> corners = {{{f.right - m - f.legend_w, f.top + m},
                                                           {f.left + m, f.top + m},
                                                           {f.right - m - f.legend_w, f.bottom - m - f.legend_h},
                                                           {f.left + m, f.bottom - m - f.legend_h}}};
    std::array<double, 4> cost{};
    const auto add = [&](double px, double py) {
        for (int c = 0; c < 4; ++c)
            if (px >= corners[c][0] - 4 && px <= corners[c][0] + f.legend_w + 4 && py >= corners[c][1] - 4 && py <= corners[c][1] + f.legend_h + 4)
                cost[c] += 1;
    };
    for (const auto& s : plot.series) {
        const std::size_t n = count(s);
        for (std::size_t k = 0; k < n; ++k) {
            if (!finite_pair(s, k)) continue;
            add(X(s.x[k]), Y(s.y[k]));
            if (has_line(s) && k + 1 < n && finite_pair(s, k + 1))
                for (int t = 1; t < 8; ++t)
                    add(X(s.x[k] + (s.x[k + 1] - s.x[k]) * t / 8.0), Y(s.y[k] + (s.y[k + 1] - s.y[k]) * t / 8.0));
        }
    }
    const int best = static_cast<int>(std::min_element(cost.begin(), cost.end()) - cost.begin());
    f.legend_x = corners[best][0];
    f.legend_y = corners[best][1];
    L.legend_covers = cost[best];
    return L;
}

/// The legend inside the axes where it fits whole and covers no data; else right of the axes
/// when they keep at least half the width there; else inside, where it covers the least.
Layout layout(cairo_t* cr, const Plot& plot, int W, int H)
{
    Layout inside = layout_with(cr, plot, W, H, false);
    const std::array<double, 2> want = legend_size(cr, plot, inside.legend_row);
    if (want[0] == 0 || (inside.legend_covers == 0 && inside.f.legend_w >= want[0] && inside.f.legend_h >= want[1])) return inside;
    Layout out = layout_with(cr, plot, W, H, true);
    if (out.f.right - out.f.left >= 0.5 * (inside.f.right - inside.f.left) && out.f.legend_w >= want[0] && out.f.legend_h >= want[1]) return out;
    inside.f.legend_whole = inside.f.legend_w >= want[0] && inside.f.legend_h >= want[1];
    return inside;
}

/// A text of the SVG drawing, written as an SVG <text> element (searchable, read by screen
/// readers) where the PNG has cairo's glyphs: its baseline's anchor point (x, y), anchored at 0
/// (start), 0.5 (middle) or 1 (end), turned -90 degrees about it when `vertical`.
struct SvgText {
    std::string text;
    double x = 0, y = 0, anchor = 0, size = 12;
    bool bold = false, vertical = false;
};

/// Draws the plot; with `texts` its text is not drawn but listed there (plot_svg writes it).
void draw(cairo_t* cr, const Plot& plot, const Layout& L, int W, int H, std::vector<SvgText>* texts = nullptr)
{
    const PlotFrame& f = L.f;
    double size = kTickSize;
    bool bold = false;
    const auto set_font = [&](double px, bool b = false) {
        font(cr, px, b);
        size = px;
        bold = b;
    };
    const auto put = [&](const std::string& s, double x, double y, double anchor, bool vertical = false) {
        if (texts)
            texts->push_back({s, x, y, anchor, size, bold, vertical});
        else
            text(cr, s, x, y, anchor);
    };
    const double aw = f.right - f.left, ah = f.bottom - f.top;
    const auto X = [&](double x) { return f.left + (x - f.x_lo) / (f.x_hi - f.x_lo) * aw; };
    const auto Y = [&](double y) { return f.bottom - (y - f.y_lo) / (f.y_hi - f.y_lo) * ah; };
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    const Vec3 ink(0.15, 0.15, 0.15);
    // Grid and ticks.
    cairo_set_line_width(cr, 1);
    color(cr, Vec3(0.9, 0.9, 0.9));
    for (double t : L.ax.ticks) {
        const double px = std::round(X(t)) + 0.5;
        cairo_move_to(cr, px, f.top);
        cairo_line_to(cr, px, f.bottom);
    }
    for (double t : L.ay.ticks) {
        const double py = std::round(Y(t)) + 0.5;
        cairo_move_to(cr, f.left, py);
        cairo_line_to(cr, f.right, py);
    }
    cairo_stroke(cr);
    color(cr, ink);
    for (double t : L.ax.ticks) {
        const double px = std::round(X(t)) + 0.5;
        cairo_move_to(cr, px, f.bottom);
        cairo_line_to(cr, px, f.bottom + 5);
    }
    for (double t : L.ay.ticks) {
        const double py = std::round(Y(t)) + 0.5;
        cairo_move_to(cr, f.left - 5, py);
        cairo_line_to(cr, f.left, py);
    }
    cairo_stroke(cr);
    set_font(kTickSize);
    for (double t : L.ax.ticks) put(tick_label(t, L.ax.step), X(t), f.bottom + 8 + kTickSize, 0.5);
    for (double t : L.ay.ticks) put(tick_label(t, L.ay.step), f.left - 8, Y(t) + 0.36 * kTickSize, 1);
    set_font(kLabelSize);
    if (!plot.x_label.empty()) put(plot.x_label, 0.5 * (f.left + f.right), H - 10.0, 0.5);
    if (!plot.y_label.empty()) {
        if (texts) {
            put(plot.y_label, 12 + kLabelSize, 0.5 * (f.top + f.bottom), 0.5, true);
        } else {
            cairo_save(cr);
            cairo_translate(cr, 12 + kLabelSize, 0.5 * (f.top + f.bottom));
            cairo_rotate(cr, -M_PI / 2);
            text(cr, plot.y_label, 0, 0, 0.5);
            cairo_restore(cr);
        }
    }
    if (!plot.title.empty()) {
        set_font(kTitleSize, true);
        put(plot.title, 0.5 * W, 22, 0.5);
    }
    // The data, clipped to the axes.
    cairo_save(cr);
    cairo_rectangle(cr, f.left, f.top, aw, ah);
    cairo_clip(cr);
    const double cx0 = f.left - 2, cx1 = f.right + 2, cy0 = f.top - 2, cy1 = f.bottom + 2;
    for (std::size_t si = 0; si < plot.series.size(); ++si) {
        const Series& s = plot.series[si];
        const Vec3& c = f.colors[si];
        const std::size_t n = count(s);
        if (has_line(s)) {
            bool open = false;  // a subpath is under way, ending at the previous point
            for (std::size_t k = 0; k + 1 < n; ++k) {
                if (!finite_pair(s, k) || !finite_pair(s, k + 1)) {
                    open = false;
                    continue;
                }
                double ax = X(s.x[k]), ay = Y(s.y[k]), bx = X(s.x[k + 1]), by = Y(s.y[k + 1]);
                const bool a_in = ax >= cx0 && ax <= cx1 && ay >= cy0 && ay <= cy1;
                const bool b_in = bx >= cx0 && bx <= cx1 && by >= cy0 && by <= cy1;
                if (!(a_in && b_in) && !clip(ax, ay, bx, by, cx0, cx1, cy0, cy1)) {
                    open = false;
                    continue;
                }
                if (!open || !a_in) cairo_move_to(cr, ax, ay);
                cairo_line_to(cr, bx, by);
                open = b_in;
            }
            color(cr, c);
            cairo_set_line_width(cr, 2);
            cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
            cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
            cairo_stroke(cr);
        }
        bool bars = false;
        for (std::size_t k = 0; k < n; ++k) {
            const double e = err_at(s, k);
            if (!finite_pair(s, k) || e == 0) continue;
            const double px = X(s.x[k]), a = Y(s.y[k] - e), b = Y(s.y[k] + e);
            cairo_move_to(cr, px, a);
            cairo_line_to(cr, px, b);
            cairo_move_to(cr, px - 4, a);
            cairo_line_to(cr, px + 4, a);
            cairo_move_to(cr, px - 4, b);
            cairo_line_to(cr, px + 4, b);
            bars = true;
        }
        if (bars) {
            color(cr, c);
            cairo_set_line_width(cr, 1.2);
            cairo_stroke(cr);
        }
        if (has_points(s)) {
            const double r = s.style == Series::Style::POINTS ? 3.5 : 3;
            for (std::size_t k = 0; k < n; ++k) {
                if (!finite_pair(s, k)) continue;
                const double px = X(s.x[k]), py = Y(s.y[k]);
                if (px < cx0 - r || px > cx1 + r || py < cy0 - r || py > cy1 + r) continue;
                cairo_new_sub_path(cr);  // a full arc, filled: no close_path (cairo would start an empty subpath after it)
                cairo_arc(cr, px, py, r, 0, 2 * M_PI);
            }
            color(cr, c);
            cairo_fill(cr);
        }
    }
    cairo_restore(cr);
    // Frame.
    color(cr, ink);
    cairo_set_line_width(cr, 1);
    cairo_rectangle(cr, f.left, f.top, aw, ah);
    cairo_stroke(cr);
    // Legend.
    if (f.legend_w > 0) {
        cairo_rectangle(cr, f.legend_x, f.legend_y, f.legend_w, f.legend_h);
        cairo_set_source_rgba(cr, 1, 1, 1, 0.92);
        cairo_fill_preserve(cr);
        color(cr, Vec3(0.8, 0.8, 0.8));
        cairo_stroke(cr);
        cairo_save(cr);
        cairo_rectangle(cr, f.legend_x, f.legend_y, f.legend_w, f.legend_h);
        cairo_clip(cr);
        set_font(kLegendSize);
        double y = f.legend_y + 8 + 0.5 * L.legend_row - 2;
        for (std::size_t si = 0; si < plot.series.size(); ++si) {
            const Series& s = plot.series[si];
            if (s.label.empty()) continue;
            const double x = f.legend_x + 8;
            color(cr, f.colors[si]);
            if (has_line(s)) {
                cairo_set_line_width(cr, 2);
                cairo_move_to(cr, x, y);
                cairo_line_to(cr, x + 26, y);
                cairo_stroke(cr);
            }
            if (has_points(s)) {
                cairo_new_path(cr);  // the text before left a current point
                cairo_arc(cr, x + 13, y, 3.5, 0, 2 * M_PI);
                cairo_fill(cr);
            }
            color(cr, ink);
            put(s.label, x + 32, y + 0.36 * kLegendSize, 0);
            y += L.legend_row;
        }
        cairo_restore(cr);
    }
}

struct CairoSurfaceDeleter {
    void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
};
struct CairoContextDeleter {
    void operator()(cairo_t* c) const { cairo_destroy(c); }
};
using CairoSurface = std::unique_ptr<cairo_surface_t, CairoSurfaceDeleter>;
using CairoContext = std::unique_ptr<cairo_t, CairoContextDeleter>;

int clamp_side(int v) { return std::clamp(v, 64, 8192); }

cairo_status_t append(void* closure, const unsigned char* data, unsigned int length)
{
    static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
    return CAIRO_STATUS_SUCCESS;
}

/// `s` with & < > " escaped for XML text.
std::string xml_escape(const std::string& s)
{
    std::string o;
    for (const char c : s) {
        switch (c) {
        case '&': o += "&amp;"; break;
        case '<': o += "&lt;"; break;
        case '>': o += "&gt;"; break;
        case '"': o += "&quot;"; break;
        default: o += c;
        }
    }
    return o;
}

/// `svg` with every id, and every reference to one, prefixed.
std::string prefix_ids(const std::string& svg, const std::string& prefix)
{
    std::string out;
    out.reserve(svg.size() + svg.size() / 16);
    for (std::size_t at = 0; at < svg.size();) {
        std::size_t best = std::string::npos, len = 0;
        for (const char* key : {"id=\"", "href=\"#", "url(#"}) {
            const std::size_t p = svg.find(key, at);
            if (p < best) {
                best = p;
                len = std::char_traits<char>::length(key);
            }
        }
        if (best == std::string::npos) {
            out.append(svg, at, std::string::npos);
            break;
        }
        out.append(svg, at, best + len - at);
        out += prefix;
        at = best + len;
    }
    return out;
}

}  // namespace

PlotFrame plot_frame(const Plot& plot, int width, int height)
{
    CairoSurface s(cairo_image_surface_create(CAIRO_FORMAT_RGB24, 1, 1));
    CairoContext cr(cairo_create(s.get()));
    return layout(cr.get(), plot, clamp_side(width), clamp_side(height)).f;
}

Image plot(const Plot& plot, int width, int height)
{
    const int W = clamp_side(width), H = clamp_side(height);
    CairoSurface s(cairo_image_surface_create(CAIRO_FORMAT_RGB24, W, H));
    if (cairo_surface_status(s.get()) != CAIRO_STATUS_SUCCESS) throw RuntimeError("plot: cairo could not make a " + std::to_string(W) + " x " + std::to_string(H) + " image");
    {
        CairoContext cr(cairo_create(s.get()));
        draw(cr.get(), plot, layout(cr.get(), plot, W, H), W, H);
    }
    cairo_surface_flush(s.get());
    Image img;
    img.width = W;
    img.height = H;
    img.rgb.resize(static_cast<std::size_t>(W) * H * 3);
    const unsigned char* data = cairo_image_surface_get_data(s.get());
    const int stride = cairo_image_surface_get_stride(s.get());
    for (int y = 0; y < H; ++y) {
        const auto* row = reinterpret_cast<const std::uint32_t*>(data + static_cast<std::ptrdiff_t>(y) * stride);
        for (int x = 0; x < W; ++x) {
            std::uint8_t* p = &img.rgb[(static_cast<std::size_t>(y) * W + x) * 3];
            p[0] = static_cast<std::uint8_t>(row[x] >> 16);
            p[1] = static_cast<std::uint8_t>(row[x] >> 8);
            p[2] = static_cast<std::uint8_t>(row[x]);
        }
    }
    return img;
}

std::string plot_svg(const Plot& plot, int width, int height, const std::string& id_prefix)
{
    const int W = clamp_side(width), H = clamp_side(height);
    std::string svg;
    std::vector<SvgText> texts;
    {
        CairoSurface s(cairo_svg_surface_create_for_stream(append, &svg, W, H));
        cairo_svg_surface_set_document_unit(s.get(), CAIRO_SVG_UNIT_PX);
        {
            CairoContext cr(cairo_create(s.get()));
            draw(cr.get(), plot, layout(cr.get(), plot, W, H), W, H, &texts);
        }
        cairo_surface_finish(s.get());
        if (cairo_surface_status(s.get()) != CAIRO_STATUS_SUCCESS) throw RuntimeError("plot: cairo could not write an SVG");
    }
    const std::size_t open = svg.find("<svg");
    if (open != std::string::npos) svg.erase(0, open);
    // A viewBox, which a page needs to scale the plot to its width (cairo writes one; kept if so).
    const std::size_t head = svg.find('>');
    if (open != std::string::npos && head != std::string::npos && svg.substr(0, head).find("viewBox") == std::string::npos)
        svg.insert(4, " viewBox=\"0 0 " + std::to_string(W) + " " + std::to_string(H) + "\"");
    // The text as <text> elements, last (on top, as the legend's is drawn), in the font the
    // layout measured (DejaVu Sans; a reader without it gets its sans-serif).
    std::string t = "<g font-family=\"DejaVu Sans, Verdana, sans-serif\" fill=\"rgb(15%,15%,15%)\">";
    for (const SvgText& x : texts) {
        char at[160];
        const char* anchor = x.anchor == 0 ? "start" : x.anchor == 1 ? "end" : "middle";
        if (x.vertical)
            std::snprintf(at, sizeof at, "<text transform=\"translate(%.2f,%.2f) rotate(-90)\" font-size=\"%gpx\" text-anchor=\"%s\"", x.x, x.y,
                          x.size, anchor);
        else
            std::snprintf(at, sizeof at, "<text x=\"%.2f\" y=\"%.2f\" font-size=\"%gpx\" text-anchor=\"%s\"", x.x, x.y, x.size, anchor);
        t += at;
        if (x.bold) t += " font-weight=\"bold\"";
        t += ">" + xml_escape(x.text) + "</text>";
    }
    t += "</g>";
    const std::size_t close = svg.rfind("</svg>");
    if (close != std::string::npos) svg.insert(close, t);
    return prefix_ids(svg, id_prefix + "-");
}

}  // namespace woven::render

#if defined(__SANITIZE_ADDRESS__)
// LeakSanitizer (the sanitizer build's tests run with detect_leaks=1): fontconfig, under cairo's
// text, keeps its configuration for the process's life and frees it nowhere; not woven's leak.
// Quietly: the report of suppressions used would add lines to every command's stderr.
extern "C" const char* __lsan_default_suppressions() { return "leak:libfontconfig.so\n"; }
extern "C" const char* __lsan_default_options() { return "print_suppressions=0"; }
#endif
