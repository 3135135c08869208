#pragma once
// Internal to render: the one text style of its plots and figure labels (cairo's DejaVu Sans,
// unhinted metrics). Defined in plot.cpp, with the sanitizer build's leak suppression.
#include <cairo.h>

namespace woven::render::detail {

/// Selects DejaVu Sans at `size_px` pixels on `cr`, with unhinted metrics.
void set_font(cairo_t* cr, double size_px, bool bold = false);

}  // namespace woven::render::detail
