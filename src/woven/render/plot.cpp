#include "woven/render/plot.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "woven/render/glyphs.hpp"

namespace woven::render {

namespace {

constexpr int kTextScale = 2;

/// A float sRGB canvas with anti-aliased drawing through coverage layers.
class Canvas {
public:
    Canvas(int w, int h) : w_(w), h_(h), rgb_(static_cast<std::size_t>(w) * h * 3, 1.0f) { }
    int width() const { return w_; }
    int height() const { return h_; }

    void blend(int x, int y, const Vec3& c, double a)
    {
        if (x < 0 || y < 0 || x >= w_ || y >= h_ || a <= 0) return;
        a = std::min(a, 1.0);
        float* p = &rgb_[(static_cast<std::size_t>(y) * w_ + x) * 3];
        for (int k = 0; k < 3; ++k) p[k] = static_cast<float>(p[k] * (1 - a) + c[k] * a);
    }

    /// Fills [x0, x1) x [y0, y1) (integers).
    void fill_rect(int x0, int y0, int x1, int y1, const Vec3& c, double a = 1)
    {
        for (int y = std::max(0, y0); y < std::min(h_, y1); ++y)
            for (int x = std::max(0, x0); x < std::min(w_, x1); ++x) blend(x, y, c, a);
    }

    Image to_image() const
    {
        Image img;
        img.width = w_;
        img.height = h_;
        img.rgb.resize(rgb_.size());
        for (std::size_t i = 0; i < rgb_.size(); ++i)
            img.rgb[i] = static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(rgb_[i], 0.0f, 1.0f)));
        return img;
    }

private:
    int w_, h_;
    std::vector<float> rgb_;
};

/// Coverage (0..1) of one series, accumulated with max so joints do not darken, clipped to a rectangle.
class Layer {
public:
    Layer(int w, int h, int cx0, int cy0, int cx1, int cy1)
        : w_(w), h_(h), cx0_(std::max(0, cx0)), cy0_(std::max(0, cy0)), cx1_(std::min(w, cx1)), cy1_(std::min(h, cy1)),
          a_(static_cast<std::size_t>(w) * h, 0.0f)
    {
    }

    /// A segment of the given width (pixels) between pixel-space points (pixel centres at +0.5).
    void segment(double x0, double y0, double x1, double y1, double width)
    {
        const double r = 0.5 * width + 1;
        const int bx0 = std::max(cx0_, static_cast<int>(std::floor(std::min(x0, x1) - r)));
        const int bx1 = std::min(cx1_, static_cast<int>(std::ceil(std::max(x0, x1) + r)));
        const int by0 = std::max(cy0_, static_cast<int>(std::floor(std::min(y0, y1) - r)));
        const int by1 = std::min(cy1_, static_cast<int>(std::ceil(std::max(y0, y1) + r)));
        const double dx = x1 - x0, dy = y1 - y0, len2 = dx * dx + dy * dy;
        for (int y = by0; y < by1; ++y)
            for (int x = bx0; x < bx1; ++x) {
                const double px = x + 0.5 - x0, py = y + 0.5 - y0;
                const double t = len2 > 0 ? std::clamp((px * dx + py * dy) / len2, 0.0, 1.0) : 0.0;
                const double ex = px - t * dx, ey = py - t * dy;
                const double d = std::sqrt(ex * ex + ey * ey);
                put(x, y, std::clamp(0.5 * width + 0.5 - d, 0.0, 1.0));
            }
    }

    /// A filled disc of radius r (pixels).
    void disc(double cx, double cy, double r)
    {
        const int bx0 = std::max(cx0_, static_cast<int>(std::floor(cx - r - 1)));
        const int bx1 = std::min(cx1_, static_cast<int>(std::ceil(cx + r + 1)));
        const int by0 = std::max(cy0_, static_cast<int>(std::floor(cy - r - 1)));
        const int by1 = std::min(cy1_, static_cast<int>(std::ceil(cy + r + 1)));
        for (int y = by0; y < by1; ++y)
            for (int x = bx0; x < bx1; ++x) {
                const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
                put(x, y, std::clamp(r + 0.5 - d, 0.0, 1.0));
            }
    }

    void composite(Canvas& canvas, const Vec3& c) const
    {
        for (int y = cy0_; y < cy1_; ++y)
            for (int x = cx0_; x < cx1_; ++x) canvas.blend(x, y, c, a_[static_cast<std::size_t>(y) * w_ + x]);
    }

    float at(int x, int y) const { return a_[static_cast<std::size_t>(y) * w_ + x]; }

    /// Raises the coverage at (x, y) to at least a.
    void put(int x, int y, double a)
    {
        float& v = a_[static_cast<std::size_t>(y) * w_ + x];
        v = std::max(v, static_cast<float>(a));
    }

private:
    int w_, h_, cx0_, cy0_, cx1_, cy1_;
    std::vector<float> a_;
};

/// Text size in pixels at kTextScale.
int text_width(const std::string& s) { return s.empty() ? 0 : detail::text_width_units(s) * kTextScale; }
constexpr int kTextHeight = 7 * kTextScale;

/// Draws text with its top-left corner at (x, y); rotated: reading upwards, (x, y) is the top-left
/// of the rotated box's baseline start, i.e. the text occupies [x, x + height) x (y - width, y].
void draw_text(Canvas& canvas, const std::string& s, int x, int y, const Vec3& c, bool rotated = false)
{
    for (const detail::GlyphBox& g : detail::glyph_boxes(s)) {
        const int x0 = static_cast<int>(std::lround(g.x0 * kTextScale)), x1 = static_cast<int>(std::lround(g.x1 * kTextScale));
        const int y0 = static_cast<int>(std::lround(g.y0 * kTextScale)), y1 = static_cast<int>(std::lround(g.y1 * kTextScale));
        if (!rotated)
            canvas.fill_rect(x + x0, y + y0, x + x1, y + y1, c);
        else
            canvas.fill_rect(x + y0, y - x1, x + y1, y - x0, c);
    }
}

struct Axis {
    double lo = 0, hi = 1;
    std::vector<double> ticks;
    double step = 0.2;
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
    }
    else if (hi - lo <= std::max(std::abs(lo), std::abs(hi)) * 1e-12 || !std::isfinite(hi - lo)) {
        if (!std::isfinite(hi - lo)) {
            lo = -1e300;
            hi = 1e300;
        }
        else {
            const double pad = lo == 0 ? 0.5 : 0.05 * std::abs(lo);
            lo -= pad;
            hi += pad;
        }
    }
    else {
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

const std::array<Vec3, 10> kTab10 = {
    Vec3(0.122, 0.467, 0.706), Vec3(1.000, 0.498, 0.055), Vec3(0.173, 0.627, 0.173), Vec3(0.839, 0.153, 0.157),
    Vec3(0.580, 0.404, 0.741), Vec3(0.549, 0.337, 0.294), Vec3(0.890, 0.467, 0.761), Vec3(0.498, 0.498, 0.498),
    Vec3(0.737, 0.741, 0.133), Vec3(0.090, 0.745, 0.812)};

}  // namespace

Image plot(const Plot& plot, int width, int height)
{
    const int W = std::clamp(width, 64, 16384), H = std::clamp(height, 64, 16384);
    Canvas canvas(W, H);
    const Vec3 black(0, 0, 0), grid_grey(0.88, 0.88, 0.88), frame_grey(0.15, 0.15, 0.15);

    // Data ranges (finite pairs only; y above y_max ignored).
    const double inf = std::numeric_limits<double>::infinity();
    double xlo = inf, xhi = -inf, ylo = inf, yhi = -inf;
    bool above_clip = false;
    for (const Series& s : plot.series) {
        const std::size_t n = std::min(s.x.size(), s.y.size());
        for (std::size_t i = 0; i < n; ++i) {
            if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
            if (plot.y_max && s.y[i] > *plot.y_max) {  // clipped: counts for neither axis
                above_clip = true;
                continue;
            }
            xlo = std::min(xlo, s.x[i]);
            xhi = std::max(xhi, s.x[i]);
            ylo = std::min(ylo, s.y[i]);
            yhi = std::max(yhi, s.y[i]);
        }
    }
    const bool clipped = above_clip && plot.y_max && std::isfinite(*plot.y_max);
    if (clipped) {
        if (!(ylo <= *plot.y_max)) ylo = *plot.y_max - 1;
        yhi = *plot.y_max;
    }
    Axis ax = make_axis(xlo, xhi, std::max(3, W / 110));
    Axis ay = make_axis(ylo, yhi, std::max(3, H / 90));
    if (clipped) {  // the clip value is the top of the axes
        ay.hi = *plot.y_max;
        while (!ay.ticks.empty() && ay.ticks.back() > ay.hi + ay.step * 1e-9) ay.ticks.pop_back();
    }

    std::vector<std::string> xlabels, ylabels;
    int ylabel_w = 0;
    for (double t : ax.ticks) xlabels.push_back(tick_label(t, ax.step));
    for (double t : ay.ticks) {
        ylabels.push_back(tick_label(t, ay.step));
        ylabel_w = std::max(ylabel_w, text_width(ylabels.back()));
    }

    // Layout of the axes rectangle [left, right) x [top, bottom).
    const int tick_len = 5, gap = 6;
    const int left = 14 + (plot.y_label.empty() ? 0 : kTextHeight + 12) + ylabel_w + gap + tick_len;
    const int right = W - std::max(20, text_width(xlabels.empty() ? "" : xlabels.back()) / 2 + 6);
    const int top = plot.title.empty() ? 20 : 20 + kTextHeight + 16;
    const int bottom = H - (14 + tick_len + gap + kTextHeight + (plot.x_label.empty() ? 0 : kTextHeight + 12));
    if (right - left < 10 || bottom - top < 10) return canvas.to_image();
    const double pw = right - left, ph = bottom - top;
    auto to_px = [&](double x) { return left + (x - ax.lo) / (ax.hi - ax.lo) * pw; };
    auto to_py = [&](double y) { return bottom - (y - ay.lo) / (ay.hi - ay.lo) * ph; };

    // Grid.
    for (double t : ax.ticks) {
        const int x = std::clamp(static_cast<int>(std::floor(to_px(t))), left, right - 1);
        canvas.fill_rect(x, top, x + 1, bottom, grid_grey);
    }
    for (double t : ay.ticks) {
        const int y = std::clamp(static_cast<int>(std::floor(to_py(t))), top, bottom - 1);
        canvas.fill_rect(left, y, right, y + 1, grid_grey);
    }

    // Data.
    Layer all(W, H, left, top, right, bottom);  // union of coverage, for the legend placement
    std::vector<Vec3> colors;
    for (std::size_t si = 0; si < plot.series.size(); ++si) {
        const Series& s = plot.series[si];
        Vec3 color = s.color;
        if (si > 0 && (color - Series{}.color).norm() < 1e-12) color = kTab10[si % kTab10.size()];
        colors.push_back(color);
        Layer layer(W, H, left, top, right + 1, bottom + 1);
        const std::size_t n = std::min(s.x.size(), s.y.size());
        const bool lines = s.style != Series::Style::POINTS;
        const bool points = s.style != Series::Style::LINE;
        auto finite = [&](std::size_t i) { return std::isfinite(s.x[i]) && std::isfinite(s.y[i]); };
        for (std::size_t i = 0; i < n; ++i) {
            if (!finite(i)) continue;
            if (lines && i + 1 < n && finite(i + 1)) {
                double x0 = s.x[i], y0 = s.y[i], x1 = s.x[i + 1], y1 = s.y[i + 1];
                if (clip(x0, y0, x1, y1, ax.lo, ax.hi, ay.lo, ay.hi)) layer.segment(to_px(x0), to_py(y0), to_px(x1), to_py(y1), 2.0);
            }
            if (points && s.x[i] >= ax.lo && s.x[i] <= ax.hi && s.y[i] >= ay.lo && s.y[i] <= ay.hi)
                layer.disc(to_px(s.x[i]), to_py(s.y[i]), 3.5);
            if (lines && !points && n == 1) layer.disc(to_px(s.x[i]), to_py(s.y[i]), 1.5);
        }
        layer.composite(canvas, color);
        for (int y = top; y < bottom; ++y)
            for (int x = left; x < right; ++x)
                all.put(x, y, layer.at(x, y));
    }

    // Frame and ticks.
    canvas.fill_rect(left - 1, top - 1, right + 1, top, frame_grey);
    canvas.fill_rect(left - 1, bottom, right + 1, bottom + 1, frame_grey);
    canvas.fill_rect(left - 1, top - 1, left, bottom + 1, frame_grey);
    canvas.fill_rect(right, top - 1, right + 1, bottom + 1, frame_grey);
    for (std::size_t i = 0; i < ax.ticks.size(); ++i) {
        const int x = std::clamp(static_cast<int>(std::floor(to_px(ax.ticks[i]))), left, right - 1);
        canvas.fill_rect(x, bottom + 1, x + 1, bottom + 1 + tick_len, frame_grey);
        draw_text(canvas, xlabels[i], x - text_width(xlabels[i]) / 2 + 1, bottom + 1 + tick_len + gap, black);
    }
    for (std::size_t i = 0; i < ay.ticks.size(); ++i) {
        const int y = std::clamp(static_cast<int>(std::floor(to_py(ay.ticks[i]))), top, bottom - 1);
        canvas.fill_rect(left - 1 - tick_len, y, left - 1, y + 1, frame_grey);
        draw_text(canvas, ylabels[i], left - 1 - tick_len - gap - text_width(ylabels[i]), y - kTextHeight / 2 + 1, black);
    }

    // Labels and title.
    if (!plot.x_label.empty())
        draw_text(canvas, plot.x_label, left + static_cast<int>(pw / 2) - text_width(plot.x_label) / 2,
                  bottom + 1 + tick_len + gap + kTextHeight + 12, black);
    if (!plot.y_label.empty())
        draw_text(canvas, plot.y_label, 14, top + static_cast<int>(ph / 2) + text_width(plot.y_label) / 2, black, true);
    if (!plot.title.empty())
        draw_text(canvas, plot.title, left + static_cast<int>(pw / 2) - text_width(plot.title) / 2, 20, black);

    // Legend in the corner with the least data under it.
    std::vector<std::size_t> listed;
    int legend_text_w = 0;
    for (std::size_t si = 0; si < plot.series.size(); ++si)
        if (!plot.series[si].label.empty()) {
            listed.push_back(si);
            legend_text_w = std::max(legend_text_w, text_width(plot.series[si].label));
        }
    if (!listed.empty()) {
        const int row = kTextHeight + 10, sample = 28, pad = 10;
        const int bw = pad + sample + 8 + legend_text_w + pad;
        const int bh = pad + static_cast<int>(listed.size()) * row - 10 + pad;
        const int m = 10;
        const std::array<std::array<int, 2>, 4> corners = {{{right - m - bw, top + m},
                                                            {left + m, top + m},
                                                            {right - m - bw, bottom - m - bh},
                                                            {left + m, bottom - m - bh}}};
        int best = 0;
        double best_cost = inf;
        for (int c = 0; c < 4; ++c) {
            double cost = 0;
            for (int y = std::max(top, corners[c][1]); y < std::min(bottom, corners[c][1] + bh); ++y)
                for (int x = std::max(left, corners[c][0]); x < std::min(right, corners[c][0] + bw); ++x) cost += all.at(x, y);
            if (cost < best_cost - 0.5) {
                best_cost = cost;
                best = c;
            }
        }
        const int bx = corners[best][0], by = corners[best][1];
        canvas.fill_rect(bx, by, bx + bw, by + bh, Vec3(1, 1, 1), 0.85);
        const Vec3 edge(0.8, 0.8, 0.8);
        canvas.fill_rect(bx, by, bx + bw, by + 1, edge);
        canvas.fill_rect(bx, by + bh - 1, bx + bw, by + bh, edge);
        canvas.fill_rect(bx, by, bx + 1, by + bh, edge);
        canvas.fill_rect(bx + bw - 1, by, bx + bw, by + bh, edge);
        for (std::size_t k = 0; k < listed.size(); ++k) {
            const Series& s = plot.series[listed[k]];
            const int ty = by + pad + static_cast<int>(k) * row;
            const double cy = ty + kTextHeight / 2.0;
            Layer mark(W, H, 0, 0, W, H);
            if (s.style != Series::Style::POINTS) mark.segment(bx + pad, cy, bx + pad + sample, cy, 2.0);
            if (s.style != Series::Style::LINE) mark.disc(bx + pad + sample / 2.0, cy, 3.5);
            mark.composite(canvas, colors[listed[k]]);
            draw_text(canvas, s.label, bx + pad + sample + 8, ty + 1, black);
        }
    }
    return canvas.to_image();
}

}  // namespace woven::render
