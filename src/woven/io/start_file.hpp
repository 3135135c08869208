#pragma once
// A drape's start state read from a file: a drape.obj or cusick.obj woven wrote for the same
// scene and grid (`woven drape --start`, `woven cusick --start`).
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "woven/common/types.hpp"
#include "woven/geometry/obstacle.hpp"
#include "woven/model/grid.hpp"

namespace woven::io {

/// Largest start file read (OBJ text), bytes.
inline constexpr std::size_t kMaxStartBytes = 256u << 20;

/// A start: one position per grid particle (m), and the file's SHA-256 (hex).
struct StartState {
    Positions x;
    std::string sha256;
    std::vector<std::size_t> line;  ///< per grid particle: the file's line of its vertex (1-based), 0 where `fallback`'s is kept
};

/// The start held in OBJ text: `v x y z` lines (m, z up, as woven writes them). Exactly
/// grid.size() vertices are the grid's particles in grid order (an uncut cloth's drape.obj);
/// otherwise each vertex has a `vt u v`, its rest position in particle spacings (model::rest_uv /
/// sigma, as a cut cloth's drape.obj and cusick.obj have them), and each cloth particle
/// (`active`, one flag per grid particle; empty: all) takes the vertex at its rest position
/// (extra vertices, such as an outline's, are ignored). Particles that are not cloth keep
/// `fallback`'s positions. Every number is a whole token read as a decimal (or exponent)
/// floating-point number, `v` lines hold exactly three and `vt` lines two: `0,5`, `0x1p-1`,
/// `3zz` and a fourth number are refused, not read as a prefix. Throws InputError(source, "v"
/// or "vt", "line N: ...") naming what differs.
StartState parse_start_obj(std::string_view text, const std::string& source, const model::Grid& grid,
                           const std::vector<char>& active, const Positions& fallback);

/// parse_start_obj of the file `path` (read bounded, a regular file; a name not ending in .obj
/// is refused: "expected a drape .obj file").
StartState load_start(const std::string& path, const model::Grid& grid, const std::vector<char>& active, const Positions& fallback);

/// Where a start's positions may lie: within `reach_m` of `centre` in every coordinate (the
/// scene's bounds, kMaxCoordinate_m about the origin; the Cusick instrument's, the specimen's
/// diameter about the disc's top centre) and strictly outside every obstacle.
struct StartBounds {
    const geometry::ObstacleSet* obstacles = nullptr;  ///< null: none
    Vec3 centre = Vec3::Zero();
    double reach_m = 0;
    const char* name = "the scene's bounds";  ///< as the message names them
};

/// A start checked as the flat start is: every cloth particle p (`active[p]`, empty: all) that
/// is not in `held` (those the job places itself: pinned, clamped) finite, within the bounds and
/// strictly outside every obstacle. Throws InputError(source, field, where(p) + ": ...") for
/// the first that is not: where(p) names the particle as the input does ("line 12", "row 0").
void check_start_positions(const Positions& x, const std::vector<char>& active, const std::vector<int>& held, const StartBounds& bounds,
                           const std::string& source, const std::string& field, const std::function<std::string(int)>& where);

}  // namespace woven::io
