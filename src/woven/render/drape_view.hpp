#pragma once
// Pictures of a drape: the cloth (a smooth surface through its particles, with thread lines)
// over its obstacles and floor, from the views of the paper's Fig. 8 (front, the corner view,
// side, top) or the scene's camera direction, framed tightly.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "woven/common/choice.hpp"
#include "woven/common/types.hpp"
#include "woven/geometry/obstacle.hpp"
#include "woven/render/raytracer.hpp"

namespace woven::render {

/// The cloth as drawn: a triangle mesh with uv in particle spacings (thread units).
struct ClothSurface {
    geometry::TriangleMesh mesh;      ///< m
    std::vector<Eigen::Vector2d> uv;  ///< one per vertex, or empty (no thread lines)
    double spacing_m = 0;             ///< particle spacing (m): how far obstacles may poke through
};

/// The particle grid (nu * nv positions, index i + nu * j, m) refined `refine` times per cell by
/// tensor-product Catmull-Rom interpolation (it passes through every particle; the grid is
/// extended linearly past its edges), so folds are smooth between particles. uv = (i, j) in
/// particle spacings; spacing_m is the mean length of the grid's edges along i. Throws
/// InputError if the sizes do not match, nu or nv < 2, or refine is not in 1..8.
ClothSurface grid_surface(const Positions& x, int nu, int nv, int refine = 3);

/// The renderer's (linear) albedo of a fabric's display colour (sRGB 0..1, the fabric file's
/// `color`); without one, terracotta.
Vec3 fabric_color(const std::optional<std::array<double, 3>>& srgb);

/// The views of Fig. 8 and the scene's own.
enum class View {
    SCENE,   ///< the scene camera's direction (or CORNER without one)
    FRONT,   ///< from -y, 12 degrees above the horizontal
    CORNER,  ///< at the (+x, -y) corner along its diagonal, 20 degrees above
    SIDE,    ///< from +x, 12 degrees above
    TOP,     ///< straight down, +y up in the picture
};

/// The views' names (common/choice.hpp), in the order --help lists them.
inline constexpr std::array<Named<View>, 5> kViewNames{
    {{View::FRONT, "front"}, {View::CORNER, "corner"}, {View::SIDE, "side"}, {View::TOP, "top"}, {View::SCENE, "scene"}}};

/// "scene", "front", "corner", "side" or "top"; std::nullopt for anything else.
std::optional<View> parse_view(const std::string& name);
/// The name parse_view reads.
std::string view_name(View view);

/// What to draw.
struct DrapeScene {
    ClothSurface cloth;
    Vec3 cloth_color{0.70, 0.28, 0.16};                ///< linear RGB albedo
    const geometry::ObstacleSet* obstacles = nullptr;  ///< may be null
    std::optional<Camera> scene_camera;                ///< the scene's camera, if it has one
};

/// The camera for a view: its direction, the vertical field of view `fov_deg`, framed tightly
/// (fit_camera) around the cloth and the obstacles other than planes.
Camera view_camera(const DrapeScene& scene, View view, double aspect, double fov_deg = 30);

/// Renders the drape: the cloth (Surface::CLOTH, priority distance its spacing), obstacles in a
/// neutral grey, planes as the floor, the key light above and behind the camera's left
/// shoulder. `options.light_dir` is replaced by that light.
Image render_drape(const DrapeScene& scene, const Camera& camera, RenderOptions options = {});

}  // namespace woven::render
