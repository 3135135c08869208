#pragma once
// A cloth surface of any outline (model::cut_surface) as Wavefront OBJ text.
#include <string>
#include <vector>

#include "woven/common/types.hpp"
#include "woven/geometry/triangle_mesh.hpp"

namespace woven::io {

/// OBJ text: a `#` header line with `comment`, `v` lines (positions, m), `vt` lines when `uv`
/// has one entry per vertex (the rest position in particle spacings: u along the weft, v along
/// the warp) and `f` triangles (1-based; `f a/a b/b c/c` with uv). Throws InputError if uv is
/// neither empty nor one per vertex.
std::string surface_obj(const geometry::TriangleMesh& mesh, const std::vector<Vec2>& uv, const std::string& comment);

}  // namespace woven::io
