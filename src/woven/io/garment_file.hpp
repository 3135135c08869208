#pragma once
// The garment file (docs/GARMENT-FORMAT.md): pattern pieces with their outlines, grain and
// placement around the body, the seams, the body (the built-in dress form or an OBJ) and the
// fabric. Lengths are given in cm and converted to m here, once (kCmToM); angles in degrees.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "woven/geometry/dress_form.hpp"
#include "woven/model/garment.hpp"

namespace woven::io {

/// The body a garment is draped on.
struct BodySpec {
    /// Absent: the built-in dress form with `form`'s sizes; given: this OBJ (resolved against
    /// the garment file's folder), in `obj_unit` units, its vertical axis x = y = 0, z up.
    std::optional<std::string> obj;
    double obj_scale = 1.0;  ///< m per OBJ unit (obj_unit "m": 1, "cm": 0.01, "mm": 0.001)
    geometry::DressFormSizes form;
};

struct GarmentSpec {
    std::string name;
    std::string source;       ///< the file (errors name it)
    std::string fabric;       ///< a built-in fabric name or a fabric .toml file (resolved)
    double spacing_m = 0.02;  ///< the thread grid's spacing
    BodySpec body;
    model::Pattern pattern;
    /// The seams' stiffness ramp, N/m: each stage a drape from the last state; the last is held.
    /// Empty: the model's thread stiffness E_t times 0.01, 0.1, 1.
    std::vector<double> seam_stiffness;
    int threads = 0;    ///< 0: all cores
    int max_steps = 0;  ///< per stage; 0: the solver's default
};

/// Allowed spacing (cm).
inline constexpr double kGarmentSpacingCm[2] = {0.2, 10.0};

/// Parses a garment file's text; `base_dir` resolves relative paths (the fabric, the body's
/// OBJ). InputError "<source>:<line>: <field>: <expected>" on bad input; unknown keys are
/// appended to `warnings`.
GarmentSpec parse_garment(std::string_view text, const std::string& source, const std::string& base_dir,
                          std::vector<std::string>* warnings = nullptr);
/// Reads and parses a garment file.
GarmentSpec load_garment(const std::string& path, std::vector<std::string>* warnings = nullptr);

}  // namespace woven::io
