#pragma once
// A drape's start state read from a file: a drape.obj or cusick.obj woven wrote for the same
// scene and grid (`woven drape --start`, `woven cusick --start`).
#include <string>
#include <string_view>
#include <vector>

#include "woven/common/types.hpp"
#include "woven/model/grid.hpp"

namespace woven::io {

/// Largest start file read (OBJ text), bytes.
inline constexpr std::size_t kMaxStartBytes = 256u << 20;

/// A start: one position per grid particle (m), and the file's SHA-256 (hex).
struct StartState {
    Positions x;
    std::string sha256;
};

/// The start held in OBJ text: `v x y z` lines (m, z up, as woven writes them). Exactly
/// grid.size() vertices are the grid's particles in grid order (an uncut cloth's drape.obj);
/// otherwise each vertex has a `vt u v`, its rest position in particle spacings (model::rest_uv /
/// sigma, as a cut cloth's drape.obj and cusick.obj have them), and each cloth particle
/// (`active`, one flag per grid particle; empty: all) takes the vertex at its rest position
/// (extra vertices, such as an outline's, are ignored). Particles that are not cloth keep
/// `fallback`'s positions. Throws InputError(source, "v" or "vt", ...) naming what differs.
StartState parse_start_obj(std::string_view text, const std::string& source, const model::Grid& grid,
                           const std::vector<char>& active, const Positions& fallback);

/// parse_start_obj of the file `path` (read bounded, a regular file; a name not ending in .obj
/// is refused: "expected a drape .obj file").
StartState load_start(const std::string& path, const model::Grid& grid, const std::vector<char>& active, const Positions& fallback);

}  // namespace woven::io
