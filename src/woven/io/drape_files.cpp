#include "woven/io/drape_files.hpp"

#include <cmath>

#include "woven/analysis/vertex_fields.hpp"
#include "woven/common/error.hpp"
#include "woven/io/gltf_file.hpp"
#include "woven/io/surface_file.hpp"

namespace woven::io {

namespace {

/// sRGB (0..1) to linear RGB, glTF's baseColorFactor (IEC 61966-2-1).
double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

}  // namespace

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
        const auto fields = analysis::vertex_fields(*d.model, *d.obstacles, *d.x, d.contact_distance, d.friction).list();
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
    for (auto& m : obstacle_gltf_meshes(*d.obstacles)) meshes.push_back(std::move(m));
    set.add("drape.glb", scene_glb(meshes));
}

}  // namespace woven::io
