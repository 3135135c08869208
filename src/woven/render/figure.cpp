#include "woven/render/figure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "woven/render/glyphs.hpp"

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

int label_width(const std::string& text, int scale) { return text.empty() ? 0 : detail::text_width_units(text) * scale; }

void draw_label(Image& img, const std::string& text, int x, int y, int scale, const Vec3& srgb)
{
    for (const detail::GlyphBox& g : detail::glyph_boxes(text))
        fill_rect(img, x + static_cast<int>(std::lround(g.x0 * scale)), y + static_cast<int>(std::lround(g.y0 * scale)),
                  x + static_cast<int>(std::lround(g.x1 * scale)), y + static_cast<int>(std::lround(g.y1 * scale)), srgb);
}

}  // namespace woven::render
