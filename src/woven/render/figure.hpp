#pragma once
// Composing figures from pictures: blank canvases, pasting, filled rectangles and discs, and
// labels (the stb_easy_font bitmap font, ASCII). All colours sRGB in 0..1.
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

/// Width in pixels of `text` drawn at `scale` (pixels per font unit; the font is 7 units high).
int label_width(const std::string& text, int scale = 2);

/// Draws `text` (ASCII, '\n' starts a new line) with its top-left corner at (x, y).
void draw_label(Image& img, const std::string& text, int x, int y, int scale = 2, const Vec3& srgb = Vec3::Zero());

}  // namespace woven::render
