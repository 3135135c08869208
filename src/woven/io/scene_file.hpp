#pragma once
// Scene files (TOML): the cloth, its fabric, the obstacles, solver and model settings and a
// camera. The format is documented in docs/SCENE-FORMAT.md; built-in scenes live in scenes/ and
// are compiled into the binary.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "woven/common/types.hpp"
#include "woven/geometry/obstacle.hpp"
#include "woven/model/cloth_model.hpp"
#include "woven/model/outline.hpp"
#include "woven/sim/drape.hpp"

namespace woven::io {

/// Largest cloth a scene may ask for (particles).
inline constexpr long long kMaxParticles = 4'000'000;
/// Plausible bounds of a scene (docs/SCENE-FORMAT.md "Bounds").
inline constexpr double kMaxCoordinate_m = 1e3;     ///< largest |coordinate| of a position (m)
inline constexpr double kMinLength_m = 1e-4;        ///< smallest obstacle size, radius, thickness (m)
inline constexpr double kMaxLength_m = 1e3;         ///< largest obstacle size (m)
inline constexpr double kMinSigma_m = 1e-4;         ///< smallest particle spacing (m)
inline constexpr double kMaxContactFraction = 1.0;  ///< largest contact distance / sigma
inline constexpr int kMaxThreads = 4096;            ///< largest thread count asked for
inline constexpr double kMaxPerturbation_m = 0.01;  ///< largest start perturbation (m)
inline constexpr double kMaxCreepSoftening = 1e4;   ///< largest creep continuation softening (threads that much softer)
inline constexpr double kMaxFallDuration_s = 100;  ///< longest fall of the fast solver held at its first step (s)

/// The cloth's starting state: a flat nu x nv grid of particles, spacing sigma, at a height.
struct ClothSpec {
    double size_u = 1;  ///< extent along the weft, i direction (m)
    double size_v = 1;  ///< extent along the warp, j direction (m)
    int nu = 51;        ///< particles along u (>= 3)
    int nv = 51;        ///< particles along v (>= 3)
    Vec3 centre{0, 0, 0.51};  ///< centre of the flat starting grid (m); z is the height
    double yaw_deg = 0;       ///< rotation of the grid about +z (degrees)
    std::vector<std::pair<int, int>> pinned;  ///< particles (i, j) held at their start positions
    std::vector<std::string> clamped_edges;   ///< whole edges held: "i0" (i = 0), "i1" (i = nu-1), "j0", "j1"

    /// The shape the cloth is cut to ([cloth.outline], docs/SCENE-FORMAT.md; default: the whole
    /// rectangle), in the cloth's rest plane relative to its centre (model/outline.hpp).
    model::Outline outline;

    /// The outline's cut of grid() (kept particles, their areas); InputError naming
    /// cloth.outline when it does not fit the grid.
    model::ClothCut cut(const std::string& source) const { return model::cut_grid(grid(), outline, source, "cloth.outline"); }
    /// True unless the outline is the whole rectangle.
    bool is_cut() const { return outline.kind != model::Outline::Kind::RECTANGLE; }
    /// Rest spacing sigma = size_u / (nu - 1) (m).
    double sigma() const { return size_u / (nu - 1); }
    /// The model's grid (nu, nv, sigma).
    model::Grid grid() const { return model::Grid{nu, nv, sigma()}; }
    /// The flat starting positions (model::flat_grid at centre, rotated by yaw_deg).
    Positions initial_positions() const;
};

/// Where the renderer looks from.
struct CameraSpec {
    Vec3 eye = Vec3(2.0, -2.6, 1.9);  ///< camera position (m)
    Vec3 target = Vec3(0, 0, 0.3);    ///< point looked at (m)
    double fov_deg = 35;              ///< vertical field of view (degrees), in (0, 180)
    bool given = false;               ///< true when the scene has a [camera] table
};

/// A parsed and built scene.
struct SceneSpec {
    std::string name;         ///< scene name (defaults to the file's stem)
    std::string description;  ///< free text
    std::string source_path;  ///< the file it came from ("scenes/<name>.toml" for built-ins)
    ClothSpec cloth;
    /// Fabric: a built-in name (no '/' and not ending in ".toml") or a path to a fabric file,
    /// resolved relative to the scene file's folder.
    std::string fabric = "cotton";
    geometry::ObstacleSet obstacles;          ///< built obstacles, in file order
    std::vector<std::string> obstacle_kinds;  ///< the scene's `type` of each obstacle ("disc", "plane", ...)
    sim::SolverOptions solver;
    model::ModelOptions model;
    CameraSpec camera;

    /// Pinned particles and all particles of the clamped edges, as indices i + nu * j, sorted,
    /// without duplicates.
    std::vector<int> pinned_indices() const;
};

/// Parses a scene from TOML text and builds its obstacles.
/// @param toml_text  the file's contents
/// @param source     the file name used in messages ("<source>: <field>: <expected>")
/// @param base_dir   folder that relative mesh and fabric paths are resolved against
/// @param warnings   receives one line per unknown key (may be null)
/// Throws InputError for TOML syntax ("<source>:<line>:<col>: ..."), unknown obstacle types,
/// missing or mistyped fields, non-finite numbers, non-positive sizes, inconsistent spacing,
/// too large grids, missing mesh files, pinned particles out of range, and a cloth starting
/// inside or touching an obstacle.
SceneSpec parse_scene(std::string_view toml_text, const std::string& source, const std::string& base_dir,
                      std::vector<std::string>* warnings = nullptr);

/// Reads and parses a scene file (relative paths in it resolve against its folder).
/// Throws InputError "<path>: file: no such scene file" if it cannot be read.
SceneSpec load_scene(const std::string& path, std::vector<std::string>* warnings = nullptr);

/// Names of the built-in scenes (embedded scenes/<name>.toml), sorted.
std::vector<std::string> builtin_scene_names();

/// A scene file if `name_or_path` names an existing file, else the built-in scene of that name
/// (meshes and fabrics of built-ins come from the embedded data). Throws InputError listing the
/// built-in names if it is neither.
SceneSpec find_scene(const std::string& name_or_path, std::vector<std::string>* warnings = nullptr);

/// Overrides from the command line; an empty optional keeps the scene's value.
struct SceneOverrides {
    /// Particles along the cloth's longer side; the cloth size is kept. A square cloth gets
    /// nu = nv = n; otherwise the shorter side gets the count closest to the same sigma and its
    /// length is adjusted to (count - 1) * sigma. Pinned (i, j) are mapped to the nearest
    /// particle of the new grid.
    std::optional<int> grid;
    std::optional<std::string> fabric;        ///< fabric name or path (as given, not re-resolved)
    std::optional<sim::SolverKind> solver;    ///< solver kind
    std::optional<std::uint64_t> seed;        ///< random seed
    std::optional<int> max_steps;             ///< >= 0 (0: the solver's default)
    std::optional<int> threads;               ///< >= 0 (0: all cores)
};

/// Applies command-line overrides to a scene and re-checks it (grid limits, the cloth not
/// starting inside an obstacle). Errors name `source` (e.g. "command line") and the option, the
/// grid's as `grid_field` (Python's keyword: "grid").
void apply_overrides(SceneSpec& scene, const SceneOverrides& overrides, const std::string& source = "command line",
                     const std::string& grid_field = "--grid");

}  // namespace woven::io
