#pragma once
// Composing figures from pictures: blank canvases, pasting, filled rectangles and discs, and
// labels (cairo's text in DejaVu Sans, anti-aliased). All colours sRGB in 0..1.
#include <string>

#include "woven/common/types.hpp"
#include "woven/render/image.hpp"

namespace woven::render {

/// A width x height image of one colour (each side clamped to 1..16384).
Image blank(int width, int height, const Vec3& srgb = Vec3(1, 1, 1));

/// Copies `src` into `dst` with its top-left corner at (x, y), clipped to `dst`.
void paste(Image& dst, const Image& src, int x, int y);

/// Fills [x0, x1) x [y0, y1), clipped, blending with opacity alpha (0..1).
void fill_rect(Image& img, int x0, int y0, int x1, int y1, const Vec3& srgb, double alpha = 1);

/// A filled, anti-aliased disc of radius r (pixels) centred at (cx, cy).
void fill_disc(Image& img, double cx, double cy, double r, const Vec3& srgb);

/// Width in pixels of `text` drawn at `scale` (the font is 6.5 * scale px, its capitals about
/// 5 * scale px high); its widest line.
int label_width(const std::string& text, int scale = 2);
/// Height in pixels of `text`'s lines from the top of the first's capitals to the last's baseline.
int label_height(const std::string& text, int scale = 2);

/// Draws `text` (UTF-8, '\n' starts a new line) with the top of its capitals at y and its
/// left end at x.
void draw_label(Image& img, const std::string& text, int x, int y, int scale = 2, const Vec3& srgb = Vec3::Zero());

}  // namespace woven::render
