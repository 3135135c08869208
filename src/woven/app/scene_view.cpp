#include "woven/app/scene_view.hpp"

#include <utility>

#include "woven/app/progress.hpp"

namespace woven::app {

render::DrapeScene scene_view(render::ClothSurface cloth, const geometry::ObstacleSet& obstacles, const kes::FabricData& fabric,
                              const io::CameraSpec* camera)
{
    render::DrapeScene ds;
    ds.cloth = std::move(cloth);
    ds.cloth_color = render::fabric_color(fabric.color);
    ds.obstacles = &obstacles;
    if (camera && camera->given) {
        render::Camera c;
        c.eye = camera->eye;
        c.target = camera->target;
        c.fov_deg = camera->fov_deg;
        ds.scene_camera = c;
    }
    return ds;
}

render::Image render_view(const render::DrapeScene& scene, render::View view, int width, int height, const std::string& what)
{
    Activity activity("rendering " + what + " (" + std::to_string(width) + " x " + std::to_string(height) + ")");
    render::RenderOptions ro;
    ro.width = width;
    ro.height = height;
    ro.progress = [&activity](double f) { activity.update(f); };
    return render::render_drape(scene, render::view_camera(scene, view, double(width) / height), ro);
}

}  // namespace woven::app
