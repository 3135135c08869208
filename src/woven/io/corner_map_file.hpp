#pragma once
// The corner map an earlier `woven experiment map` wrote (corner_map.json), read back so that
// `experiment map --reuse` can analyse its drapes again without draping. It is input like any
// other: read bounded (io::read_input_file), every field checked, errors in the one-line form
// "<file>: <field>: expected <what>" (exit 2).
//
// The form read (the fields the map uses; others are kept as they are):
//   {"command": "...", "version": "...",
//    "cells": [{"ratio_warp_weft": r > 0, "bending_length_cm": c > 0, "converged": bool,
//               "folds": null | {"corners": [4 x {"angles_deg": [[deg, ...], ...],
//                                               "standout_m": [[m, ...], ...]}]}}, ...]}
// where angles_deg and standout_m hold one list per section (the first is the one the map
// classifies), each standout_m list as long as its angles_deg list.
#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "woven/analysis/folds.hpp"

namespace woven::io {

inline constexpr std::size_t kMaxCornerMapBytes = 16u << 20;  ///< largest corner_map.json read (16 MiB)
inline constexpr int kMaxCornerMapDepth = 16;                  ///< JSON nesting (the map's own is 6 deep)
inline constexpr std::size_t kMaxCornerMapCells = 1000;        ///< cells (a 9 x 9 map has 81)

/// One cell of a corner map.
struct CornerMapCell {
    double ratio_warp_weft = 0;
    double bending_length_cm = 0;
    bool converged = false;
    bool has_folds = false;  ///< false: "folds" was null (no box to analyse)
    /// The billows of each corner on the first section (corner, angle_deg, standout_m set).
    std::array<std::vector<analysis::Billow>, 4> corners;
    nlohmann::json json;  ///< the cell as read
};

struct CornerMap {
    std::string command, version;  ///< "" when absent
    std::vector<CornerMapCell> cells;
};

/// Parses corner_map.json text; InputError naming `source` and the field on anything else.
CornerMap parse_corner_map(std::string_view text, const std::string& source);

/// Reads and parses the file at `path` (at most kMaxCornerMapBytes, a regular file).
CornerMap load_corner_map(const std::string& path);

}  // namespace woven::io
