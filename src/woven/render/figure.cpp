#include "woven/render/figure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include <cairo.h>

#include "woven/render/text.hpp"

namespace woven::render {

namespace {

std::uint8_t byte(double c) { return static_cast<std::uint8_t>(std::lround(255.0 * std::clamp(c, 0.0, 1.0))); }

void blend(Image& img, int x, int y, const Vec3& srgb, double a)
{
    if (x < 0 || y < 0 || x >= img.width || y >= img.height || a <= 0) return;
    a = std::min(a, 1.0);
    std::uint8_t* p = &img.rgb[(static_cast<std::size_t>(y) * img.width + x) * 3];
    for (int k = 0; k < 3; ++k) p[k] = byte((p[k] / 255.0) * (1 - a) + srgb[k] * a);
}

}  // namespace

Image blank(int width, int height, const Vec3& srgb)
{
    Image img;
    img.width = std::clamp(width, 1, 16384);
    img.height = std::clamp(height, 1, 16384);
    img.rgb.resize(static_cast<std::size_t>(img.width) * img.height * 3);
    for (std::size_t i = 0; i < img.rgb.size(); i += 3)
        for (int k = 0; k < 3; ++k) img.rgb[i + k] = byte(srgb[k]);
    return img;
}

void paste(Image& dst, const Image& src, int x, int y)
{
    for (int r = 0; r < src.height; ++r) {
        const int yy = y + r;
        if (yy < 0 || yy >= dst.height) continue;
        for (int c = 0; c < src.width; ++c) {
            const int xx = x + c;
            if (xx < 0 || xx >= dst.width) continue;
            for (int k = 0; k < 3; ++k)
                dst.rgb[(static_cast<std::size_t>(yy) * dst.width + xx) * 3 + k] =
                    src.rgb[(static_cast<std::size_t>(r) * src.width + c) * 3 + k];
        }
    }
}

void fill_rect(Image& img, int x0, int y0, int x1, int y1, const Vec3& srgb, double alpha)
{
    for (int y = std::max(0, y0); y < std::min(img.height, y1); ++y)
        for (int x = std::max(0, x0); x < std::min(img.width, x1); ++x) blend(img, x, y, srgb, alpha);
}

void fill_disc(Image& img, double cx, double cy, double r, const Vec3& srgb)
{
    for (int y = static_cast<int>(std::floor(cy - r - 1)); y <= static_cast<int>(std::ceil(cy + r + 1)); ++y)
        for (int x = static_cast<int>(std::floor(cx - r - 1)); x <= static_cast<int>(std::ceil(cx + r + 1)); ++x)
            blend(img, x, y, srgb, std::clamp(r + 0.5 - std::hypot(x + 0.5 - cx, y + 0.5 - cy), 0.0, 1.0));
}

namespace {

/// DejaVu Sans at 6.5 px per scale unit (scale 2: 13 px, its capitals ~9.5 px high), unhinted.
double font_px(int scale) { return 6.5 * std::max(scale, 1); }

void set_font(cairo_t* cr, int scale) { detail::set_font(cr, font_px(scale)); }

std::vector<std::string> lines_of(const std::string& text)
{
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
    return lines;
}

/// A context on a small scratch surface, for measuring.
struct Measure {
    cairo_surface_t* s = cairo_image_surface_create(CAIRO_FORMAT_A8, 1, 1);
    cairo_t* cr = cairo_create(s);
    explicit Measure(int scale) { set_font(cr, scale); }
    ~Measure()
    {
        cairo_destroy(cr);
        cairo_surface_destroy(s);
    }
    double width(const std::string& t)
    {
        cairo_text_extents_t e;
        cairo_text_extents(cr, t.c_str(), &e);
        return e.x_advance;
    }
};

}  // namespace

int label_width(const std::string& text, int scale)
{
    Measure m(scale);
    double w = 0;
    for (const auto& l : lines_of(text)) w = std::max(w, m.width(l));
    return static_cast<int>(std::ceil(w));
}

int label_height(const std::string& text, int scale)
{
    const auto n = lines_of(text).size();
    return n == 0 ? 0 : static_cast<int>(std::ceil(font_px(scale) * (1.2 * static_cast<double>(n - 1) + 1.0)));
}

void draw_label(Image& img, const std::string& text, int x, int y, int scale, const Vec3& srgb)
{
    const int w = label_width(text, scale) + 4, h = label_height(text, scale) + static_cast<int>(std::ceil(0.3 * font_px(scale))) + 4;
    if (w <= 4 || img.width <= 0) return;
    // The text's coverage on an alpha surface, blended into the image in its colour.
    cairo_surface_t* s = cairo_image_surface_create(CAIRO_FORMAT_A8, w, h);
    cairo_t* cr = cairo_create(s);
    set_font(cr, scale);
    cairo_font_extents_t fe;
    cairo_font_extents(cr, &fe);
    const auto lines = lines_of(text);
    for (std::size_t k = 0; k < lines.size(); ++k) {
        // The top of a capital at the label's top: the baseline a cap height (~0.73 em) below.
        cairo_move_to(cr, 0, 0.73 * font_px(scale) + 1.2 * font_px(scale) * static_cast<double>(k));
        cairo_show_text(cr, lines[k].c_str());
    }
    cairo_destroy(cr);
    cairo_surface_flush(s);
    const unsigned char* a = cairo_image_surface_get_data(s);
    const int stride = cairo_image_surface_get_stride(s);
    for (int r = 0; r < h; ++r)
        for (int c = 0; c < w; ++c) blend(img, x + c, y + r, srgb, a[static_cast<std::ptrdiff_t>(r) * stride + c] / 255.0);
    cairo_surface_destroy(s);
}

}  // namespace woven::render
