#pragma once
// Output writers: atomic file writes and the draped cloth as a mesh (OBJ, PLY).
//
// Grid convention (model/grid.hpp, docs/MODEL.md): particle (i, j) has index i + nu * j;
// weft threads run along i (u), warp threads along j (v). Each grid cell
// (i, j)-(i+1, j)-(i+1, j+1)-(i, j+1) gives two triangles,
//   (i, j) (i+1, j) (i+1, j+1)   and   (i, j) (i+1, j+1) (i, j+1),
// counter-clockwise seen from +z for a flat grid laid out as model::flat_grid lays it out.
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "woven/analysis/vertex_fields.hpp"
#include "woven/common/types.hpp"

namespace woven::io {

/// Writes `contents` to `path` atomically: the data goes to a unique temporary name in the same
/// folder (".woven-tmp.<pid>.a<n>.<name>"), which is then renamed over `path` (no fsync). On any failure the temporary file is removed and RuntimeError is
/// thrown; `path` is never left holding a partial file.
void write_file_atomic(const std::string& path, std::string_view contents);

/// The cloth grid as Wavefront OBJ text: a header comment (units m, grid nu x nv), `v` lines
/// (positions, m), `vt` lines (u = i / (nu - 1) along the weft, v = j / (nv - 1) along the warp),
/// `vn` lines (geometry::vertex_normals) and two `f v/vt/vn` triangles per grid cell (geometry::grid_mesh's) (1-based indices; the
/// three arrays share particle order). Throws InputError if x.size() != nu * nv or nu, nv < 2.
std::string cloth_obj(const Positions& x, int nu, int nv);

/// PLY's two encodings: binary little-endian (compact, exact) or ASCII (readable).
enum class PlyFormat { BINARY, ASCII };

/// The cloth grid as PLY 1.0: vertex properties x y z (double, m), nx ny nz u v (float; u, v as in
/// cloth_obj), then one float property per field (its name; the header's comments give each
/// unit), and `3 a b c` triangle faces (uchar count, int indices, 0-based), the same triangles as
/// cloth_obj. Comments give the units and the grid. Throws InputError if x.size() != nu * nv,
/// nu, nv < 2 or a field does not have one value per particle.
std::string cloth_ply(const Positions& x, int nu, int nv, const std::vector<analysis::VertexField>& fields = {},
                      PlyFormat format = PlyFormat::BINARY);

}  // namespace woven::io
