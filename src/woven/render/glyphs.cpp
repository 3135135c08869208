#include "woven/render/glyphs.hpp"

#include <algorithm>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb/stb_easy_font.h>
#pragma GCC diagnostic pop

namespace woven::render::detail {

std::vector<GlyphBox> glyph_boxes(const std::string& text)
{
    std::vector<GlyphBox> boxes;
    if (text.empty()) return boxes;
    std::vector<char> buf(text.begin(), text.end());
    buf.push_back('\0');
    std::vector<char> vbuf(text.size() * 300 + 1024);
    const int quads = stb_easy_font_print(0, 0, buf.data(), nullptr, vbuf.data(), static_cast<int>(vbuf.size()));
    struct Vertex {
        float x, y, z;
        unsigned char c[4];
    };
    const auto* v = reinterpret_cast<const Vertex*>(vbuf.data());
    for (int q = 0; q < quads; ++q) {
        GlyphBox b{v[4 * q].x, v[4 * q].y, v[4 * q].x, v[4 * q].y};
        for (int k = 1; k < 4; ++k) {
            b.x0 = std::min(b.x0, v[4 * q + k].x);
            b.x1 = std::max(b.x1, v[4 * q + k].x);
            b.y0 = std::min(b.y0, v[4 * q + k].y);
            b.y1 = std::max(b.y1, v[4 * q + k].y);
        }
        boxes.push_back(b);
    }
    return boxes;
}

int text_width_units(const std::string& text)
{
    std::vector<char> buf(text.begin(), text.end());
    buf.push_back('\0');
    return stb_easy_font_width(buf.data());
}

}  // namespace woven::render::detail
