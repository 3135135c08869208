#pragma once
// The picture of a draped cloth in its scene, one way for every subcommand that draws one.
#include <string>

#include "woven/io/scene_file.hpp"
#include "woven/kes/fabric.hpp"
#include "woven/render/drape_view.hpp"

namespace woven::app {

/// The cloth surface over `obstacles` in the fabric's colour, with the scene's camera if it
/// gives one. `obstacles` must outlive the result.
render::DrapeScene scene_view(render::ClothSurface cloth, const geometry::ObstacleSet& obstacles, const kes::FabricData& fabric,
                              const io::CameraSpec* camera = nullptr);

/// A width x height picture of `scene` from `view`, framed tightly; its progress is an activity
/// naming `what` (progress.hpp Activity).
render::Image render_view(const render::DrapeScene& scene, render::View view, int width, int height,
                          const std::string& what = "picture");

}  // namespace woven::app
