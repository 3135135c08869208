// The instruments' and experiments' plots and pictures (instrument_plots.hpp).
#include "woven/render/instrument_plots.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iomanip>
#include <sstream>

#include "woven/common/format.hpp"
#include "woven/render/figure.hpp"

namespace woven::render {

namespace {

}  // namespace

Plot kes_loop_plot(const std::string& title, const std::string& x_label, const std::string& y_label, const std::vector<KesCurveView>& runs,
                   bool page)
{
    Plot p{title, x_label, y_label, {}, {}, false};
    std::vector<Series> inputs, sims;
    for (const auto& r : runs) {
        const bool weft = r.direction == "weft";
        Series in{r.input_x, r.input_y, Series::Style::LINE, std::nullopt, (page ? "input " : "input loop ") + r.direction, {}};
        Series sim{r.x, r.y, Series::Style::POINTS, std::nullopt, "simulated " + r.direction, {}};
        if (page) {
            in.color = weft ? kGreen : kBlue;
            sim.color = weft ? kRed : kOrange;
        }
        // One input where the directions share it (shear): drawn and labelled once.
        if (std::none_of(inputs.begin(), inputs.end(), [&](const Series& s) { return s.x == in.x && s.y == in.y; })) inputs.push_back(in);
        sims.push_back(sim);
    }
    if (inputs.size() == 1 && (page || sims.size() > 1)) inputs[0].label = page ? "input" : "input loop";
    for (auto& s : inputs) p.series.push_back(std::move(s));
    for (auto& s : sims) p.series.push_back(std::move(s));
    return p;
}

Plot kes_curve_plot(const std::string& title, const std::string& x_label, const std::string& y_label, const std::vector<KesCurveView>& runs,
                    bool per_direction)
{
    Plot p{title, x_label, y_label, {}, {}, false};
    for (const auto& r : runs) {
        if (per_direction || &r == &runs.front())
            p.series.push_back({r.input_x, r.input_y, Series::Style::POINTS, std::nullopt, "input " + (per_direction ? r.direction : "curve"), {}});
        p.series.push_back({r.x, r.y, Series::Style::LINE_AND_POINTS, std::nullopt, "simulated " + r.direction, {}});
    }
    return p;
}

Plot curve_fit_plot(const CurveFitView& c)
{
    Plot p{c.title, c.x_label, c.y_label, {}, {}, false};
    p.series.push_back({c.data_x, c.data_y, Series::Style::POINTS, Vec3(0.2, 0.2, 0.2), "KES data", {}});
    p.series.push_back({c.fit_x, c.fit_y, Series::Style::LINE, c.fit_colour, "fit (Sec. 5.1)", {}});
    if (!c.junction_x.empty()) p.series.push_back({c.junction_x, c.junction_y, Series::Style::POINTS, Vec3(0.84, 0.15, 0.16), "segment junctions", {}});
    return p;
}

Image shadow_picture(const std::vector<unsigned char>& covered, int pixels, double specimen_radius, double disc_radius,
                     const std::vector<double>& node_angle_deg, const std::vector<double>& node_radius_m, double dc_percent)
{
    const int n = pixels;
    const double half = shadow_half_width(specimen_radius);
    const double px = 2 * half / n;
    Image img;
    img.width = img.height = n;
    img.rgb.assign(3 * static_cast<size_t>(n) * n, 255);
    const auto set = [&img](int x, int y, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
        if (x < 0 || y < 0 || x >= img.width || y >= img.height) return;
        std::uint8_t* p = &img.rgb[3 * (static_cast<size_t>(y) * img.width + x)];
        p[0] = r;
        p[1] = g;
        p[2] = b;
    };
    for (int row = 0; row < n; ++row)
        for (int col = 0; col < n; ++col)
            if (covered[col + static_cast<size_t>(n) * row]) set(col, n - 1 - row, 0, 0, 0);
    const auto to_px = [&](double x, double y) { return std::pair<int, int>{static_cast<int>((x + half) / px), n - 1 - static_cast<int>((y + half) / px)}; };
    const auto circle = [&](double rad, std::uint8_t R, std::uint8_t G, std::uint8_t B) {
        const int count = static_cast<int>(2 * M_PI * rad / px * 2);
        for (int k = 0; k < count; ++k) {
            const double a = 2 * M_PI * k / count;
            const auto [x, y] = to_px(rad * std::sin(a), rad * std::cos(a));
            for (int d = 0; d < 2; ++d) set(x + d, y, R, G, B);
        }
    };
    circle(specimen_radius, 150, 150, 150);
    circle(disc_radius, 40, 90, 220);
    // Axes: warp up (+y), weft right (+x), dotted grey through the centre.
    for (int k = 0; k < n; k += 4) {
        set(n / 2, k, 170, 170, 170);
        set(k, n / 2, 170, 170, 170);
    }
    const Vec3 red(200 / 255.0, 0, 0);
    draw_label(img, "warp (0 deg)", n / 2 + 6, 6, 2, red);
    draw_label(img, "weft (90 deg)", n - label_width("weft (90 deg)") - 6, n / 2 + 8, 2, red);
    for (std::size_t k = 0; k < node_angle_deg.size() && k < node_radius_m.size(); ++k) {
        const double a = node_angle_deg[k] * M_PI / 180;
        for (double t = node_radius_m[k]; t < specimen_radius * 1.06; t += 0.5 * px) {
            const auto [x, y] = to_px(t * std::sin(a), t * std::cos(a));
            set(x, y, 220, 0, 0);
            set(x + 1, y, 220, 0, 0);
        }
    }
    std::ostringstream label;
    label << "DC " << std::fixed << std::setprecision(1) << dc_percent << " %, " << node_angle_deg.size() << " nodes";
    draw_label(img, label.str(), 6, n - 8 - label_height(label.str()));
    return img;
}

Image corner_map_picture(const std::vector<MapCellView>& cells, const std::vector<double>& ratios, const std::vector<double>& lengths,
                         const std::vector<MapMark>& mark_list, const std::vector<std::string>& structures, const std::string& footer)
{
    const int nr = static_cast<int>(ratios.size()), nc = static_cast<int>(lengths.size());
    const int cw = 190, ch = 110, left = 120, top = 60, bottom = 150;
    Image img = blank(left + cw * nc + 30, top + ch * nr + bottom);
    const Vec3 colour[4] = {Vec3(0.55, 0.80, 0.55), Vec3(0.96, 0.72, 0.45), Vec3(0.55, 0.68, 0.90), Vec3(0.85, 0.85, 0.85)};
    draw_label(img, "Corner structure over the cube, 0.10 m below its top", left, 15, 2);
    // Placement without overprint: a cell's text sits at its top, or at its bottom when a fabric's
    // mark falls on the top; a mark's name goes right of its dot, else left, below or above,
    // wherever it covers no cell text and no other mark.
    struct Box {
        int x0, y0, x1, y1;
        bool hits(const Box& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
    };
    const auto text_box = [](const std::string& t, int x, int y) {  // with a 3 px margin (and the descenders)
        return Box{x - 3, y - 3, x + label_width(t, 2) + 3, y + label_height(t, 2) + 6};
    };
    struct Mark {
        double px, py;
        std::string name;
        Box dot;
    };
    std::vector<Mark> marks;
    for (const MapMark& f : mark_list) {
        // x linear in the bending length between cell centres, y linear in log2(ratio).
        const double fx = (f.length_cm - lengths.front()) / (lengths.back() - lengths.front());
        const double fy = (std::log2(f.ratio) - std::log2(ratios.front())) / (std::log2(ratios.back()) - std::log2(ratios.front()));
        const double px = left + cw / 2.0 + fx * cw * (nc - 1), py = top + ch / 2.0 + (1 - fy) * ch * (nr - 1);
        marks.push_back({px, py, f.name, Box{static_cast<int>(px) - 9, static_cast<int>(py) - 9, static_cast<int>(px) + 9, static_cast<int>(py) + 9}});
    }
    std::vector<Box> taken;
    for (const Mark& m : marks) taken.push_back(m.dot);
    for (std::size_t k = 0; k < cells.size(); ++k) {
        const MapCellView& c = cells[k];
        const int ri = static_cast<int>(k) / nc, ci = static_cast<int>(k) % nc;
        const int x0 = left + ci * cw, y0 = top + (nr - 1 - ri) * ch;  // ratio grows upwards
        fill_rect(img, x0 + 2, y0 + 2, x0 + cw - 2, y0 + ch - 2, colour[c.structure & 3]);
        std::string t = strf("billows %.2f", c.mean_billows) + "\n" + (c.mean_abs_angle_deg > 0 ? strf("%.0f deg off", c.mean_abs_angle_deg) : std::string("")) +
                        (c.converged ? "" : "\nnot converged");
        Box b = text_box(t, x0 + 10, y0 + 10);
        const auto on_a_mark = [&](const Box& box) { return std::any_of(marks.begin(), marks.end(), [&](const Mark& m) { return m.dot.hits(box); }); };
        if (on_a_mark(b)) {
            const Box low = text_box(t, x0 + 10, y0 + ch - 4 - (b.y1 - b.y0));
            if (!on_a_mark(low)) b = low;
        }
        draw_label(img, t, b.x0 + 3, b.y0 + 3, 2);
        taken.push_back(b);
    }
    for (const Mark& m : marks) {
        const int w = label_width(m.name, 2), x = static_cast<int>(m.px), y = static_cast<int>(m.py);
        const Box candidates[] = {{x + 11, y - 9, x + 14 + w, y + 9}, {x - 14 - w, y - 9, x - 11, y + 9},
                                  {x - w / 2 - 3, y + 11, x + w / 2 + 3, y + 29}, {x - w / 2 - 3, y - 29, x + w / 2 + 3, y - 11}};
        Box label = candidates[0];
        for (const Box& cand : candidates)
            if (std::none_of(taken.begin(), taken.end(), [&](const Box& t) { return t.hits(cand) && !(t.x0 == m.dot.x0 && t.y0 == m.dot.y0); })) {
                label = cand;
                break;
            }
        taken.push_back(label);
        fill_rect(img, label.x0, label.y0, label.x1, label.y1, Vec3(1, 1, 1), 0.85);
        fill_disc(img, m.px, m.py, 7, Vec3(0, 0, 0));
        draw_label(img, m.name, label.x0 + 3, label.y0 + 3, 2);
    }
    for (std::size_t f = 0; f < marks.size(); ++f) fill_disc(img, marks[f].px, marks[f].py, 4.5, mark_list[f].colour);
    for (int ri = 0; ri < nr; ++ri) draw_label(img, strf("%.3g", ratios[ri]), 20, top + (nr - 1 - ri) * ch + ch / 2 - 7, 2);
    for (int ci = 0; ci < nc; ++ci) draw_label(img, strf("%.2g cm", lengths[ci]), left + ci * cw + cw / 2 - 25, top + nr * ch + 8, 2);
    draw_label(img, "warp/weft", 10, top - 25, 2);
    draw_label(img, "bending length c = (B/W)^(1/3), B = sqrt(B_warp B_weft)", left, top + nr * ch + 30, 2);
    int ly = top + nr * ch + 60, lx = left;
    for (std::size_t s = 0; s < structures.size(); ++s) {
        fill_rect(img, lx, ly, lx + 20, ly + 14, colour[s & 3]);
        draw_label(img, structures[s], lx + 26, ly, 2);
        lx += 40 + label_width(structures[s], 2);
        if (lx > left + cw * nc - 200) {
            lx = left;
            ly += 24;
        }
    }
    draw_label(img, footer, left, top + nr * ch + bottom - 30, 2, Vec3(0.3, 0.3, 0.3));
    return img;
}

}  // namespace woven::render
