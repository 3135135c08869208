#include "woven/io/drape_files.hpp"

#include <cmath>
#include <cstdio>

#include "woven/analysis/vertex_fields.hpp"
#include "woven/common/error.hpp"
#include "woven/geometry/display_surface.hpp"
#include "woven/io/gltf_file.hpp"
#include "woven/io/surface_file.hpp"
#include "woven/sim/solver_support.hpp"

namespace woven::io {

namespace {

/// sRGB (0..1) to linear RGB, glTF's baseColorFactor (IEC 61966-2-1).
double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

}  // namespace

analysis::VertexFields drape_vertex_fields(const DrapeMeshes& d)
{
    return analysis::vertex_fields(*d.model, *d.obstacles, *d.x, d.contact_distance,
                                   sim::residual_forces(*d.model, *d.obstacles, *d.x, d.contact_distance, d.friction));
}

void add_drape_meshes(OutputSet& set, const DrapeMeshes& d)
{
    const model::Grid& grid = d.model->grid();
    std::vector<GltfMesh> meshes;
    if (d.cut) {
        set.add("drape.obj", surface_obj(*d.cut, *d.cut_uv, d.cut_comment));
        GltfMesh cloth;
        cloth.name = "cloth";
        cloth.mesh = *d.cut;
        cloth.uv = *d.cut_uv;
        cloth.double_sided = true;
        meshes.push_back(std::move(cloth));
    } else {
        const auto fields = drape_vertex_fields(d).list();
        // As every number of a run's outputs: none non-finite (run_checks.hpp's rule).
        for (const auto& f : fields)
            for (std::size_t p = 0; p < f.values.size(); ++p)
                if (!std::isfinite(f.values[p]))
                    throw RuntimeError("the drape ended with a non-finite " + f.name + " at particle " + std::to_string(p) +
                                       "; no outputs written");
        set.add("drape.obj", cloth_obj(*d.x, grid.nu, grid.nv));
        set.add("drape.ply", cloth_ply(*d.x, grid.nu, grid.nv, fields, d.ply));
        meshes.push_back(cloth_gltf_mesh(*d.x, grid.nu, grid.nv, fields));
    }
    if (d.color)
        for (int c = 0; c < 3; ++c) meshes[0].color[c] = srgb_to_linear((*d.color)[c]);
    // The glTF's cloth is for display: lifted off the obstacles by the contact distance so that
    // no obstacle's edge shows through the flat triangles between the particles (drape.obj and
    // drape.ply hold the particles as they are; the fields stay per particle).
    const geometry::LiftedSurface shown = geometry::lift_off_obstacles(meshes[0].mesh, *d.obstacles, d.contact_distance);
    meshes[0].mesh = shown.mesh;
    char holds[300];
    std::snprintf(holds, sizeof holds,
                  "display surface: the cloth's vertices lifted off the obstacles (at most %.3g m) so that its triangles clear them by "
                  "the contact distance %.3g m; drape.obj and drape.ply hold the particles as solved",
                  shown.max_lift, d.contact_distance);
    meshes[0].holds = holds;
    for (auto& m : obstacle_gltf_meshes(*d.obstacles)) meshes.push_back(std::move(m));
    set.add("drape.glb", scene_glb(meshes));
}

std::string draped_surface_glb(const geometry::TriangleMesh& surface, const std::vector<Vec2>& uv, const geometry::ObstacleSet& obstacles,
                               double contact_distance, const std::optional<std::array<double, 3>>& color)
{
    std::vector<GltfMesh> meshes(1);
    GltfMesh& cloth = meshes[0];
    cloth.name = "cloth";
    const geometry::LiftedSurface shown = geometry::lift_off_obstacles(surface, obstacles, contact_distance);
    cloth.mesh = shown.mesh;
    cloth.uv = uv;
    cloth.double_sided = true;
    if (color)
        for (int c = 0; c < 3; ++c) cloth.color[c] = srgb_to_linear((*color)[c]);
    char holds[300];
    std::snprintf(holds, sizeof holds,
                  "display surface: the draped surface lifted off the obstacles (at most %.3g m) so that its triangles clear them by "
                  "the contact distance %.3g m; the .obj file holds it as solved",
                  shown.max_lift, contact_distance);
    cloth.holds = holds;
    for (auto& m : obstacle_gltf_meshes(obstacles)) meshes.push_back(std::move(m));
    return scene_glb(meshes);
}

}  // namespace woven::io
