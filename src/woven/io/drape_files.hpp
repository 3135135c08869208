#pragma once
// The meshes of a drape as files of an output set: drape.obj and drape.ply, with the
// per-particle fields of analysis/vertex_fields.hpp in the PLY (drape.glb: render/gltf_file.hpp).
#include <string>
#include <vector>

#include "woven/analysis/vertex_fields.hpp"
#include "woven/common/types.hpp"
#include "woven/geometry/obstacle.hpp"
#include "woven/geometry/triangle_mesh.hpp"
#include "woven/io/output.hpp"
#include "woven/io/output_set.hpp"
#include "woven/model/cloth_model.hpp"

namespace woven::io {

struct DrapeMeshes {
    const Positions* x = nullptr;  ///< the drape, one position per grid particle (m)
    const model::ClothModel* model = nullptr;
    const geometry::ObstacleSet* obstacles = nullptr;
    double contact_distance = 0;  ///< m, the solver's
    double friction = 0;          ///< the solver's
    PlyFormat ply = PlyFormat::BINARY;
    /// A cloth cut to an outline: its surface clipped to the outline (m) and texture coordinates;
    /// then drape.obj holds it (no fields: its vertices are not the particles) and no drape.ply
    /// is written.
    const geometry::TriangleMesh* cut = nullptr;
    const std::vector<Vec2>* cut_uv = nullptr;
    std::string cut_comment;  ///< drape.obj's header comment for a cut cloth
};

/// The per-particle fields of a drape (analysis/vertex_fields.hpp), its residual forces those the
/// solver measures (sim::residual_forces) with the drape's contact distance and friction.
analysis::VertexFields drape_vertex_fields(const DrapeMeshes& d);

/// Adds drape.obj and drape.ply (the grid; not for a cut cloth) to `set` and returns the fields
/// the PLY holds (none for a cut cloth). RuntimeError when a field is not finite (nothing is
/// added then; the set is not published).
std::vector<analysis::VertexField> add_drape_meshes(OutputSet& set, const DrapeMeshes& d);

}  // namespace woven::io
