#pragma once
// Internal to render: the filled boxes of a text in stb_easy_font's pixel font (font units: one
// unit a pixel at scale 1, the text's top-left at (0, 0)), for the plot and figure labels.
#include <string>
#include <vector>

namespace woven::render::detail {

struct GlyphBox {
    float x0, y0, x1, y1;  ///< font units, x right, y down
};

/// The quads stb_easy_font draws for `text`, each as its bounding box.
std::vector<GlyphBox> glyph_boxes(const std::string& text);
/// The text's width in font units.
int text_width_units(const std::string& text);

}  // namespace woven::render::detail
