#include "woven/io/drape_files.hpp"

#include <cmath>

#include "woven/analysis/vertex_fields.hpp"
#include "woven/common/error.hpp"
#include "woven/io/surface_file.hpp"
#include "woven/sim/solver_support.hpp"

namespace woven::io {

analysis::VertexFields drape_vertex_fields(const DrapeMeshes& d)
{
    return analysis::vertex_fields(*d.model, *d.obstacles, *d.x, d.contact_distance,
                                   sim::residual_forces(*d.model, *d.obstacles, *d.x, d.contact_distance, d.friction));
}

std::vector<analysis::VertexField> add_drape_meshes(OutputSet& set, const DrapeMeshes& d)
{
    if (d.cut) {
        set.add("drape.obj", surface_obj(*d.cut, *d.cut_uv, d.cut_comment));
        return {};
    }
    const model::Grid& grid = d.model->grid();
    auto fields = drape_vertex_fields(d).list();
    // As every number of a run's outputs: none non-finite (run_checks.hpp's rule).
    for (const auto& f : fields)
        for (std::size_t p = 0; p < f.values.size(); ++p)
            if (!std::isfinite(f.values[p]))
                throw RuntimeError("the drape ended with a non-finite " + f.name + " at particle " + std::to_string(p) +
                                   "; no outputs written");
    set.add("drape.obj", cloth_obj(*d.x, grid.nu, grid.nv));
    set.add("drape.ply", cloth_ply(*d.x, grid.nu, grid.nv, fields, d.ply));
    return fields;
}

}  // namespace woven::io
