#pragma once
// The meshes of a drape as files of an output set: drape.obj, drape.ply and drape.glb, with the
// per-particle fields of analysis/vertex_fields.hpp in the PLY and the glTF.
#include <array>
#include <optional>

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
    /// then drape.obj and drape.glb hold it (no fields: its vertices are not the particles) and
    /// no drape.ply is written.
    const geometry::TriangleMesh* cut = nullptr;
    const std::vector<Vec2>* cut_uv = nullptr;
    std::string cut_comment;  ///< drape.obj's header comment for a cut cloth
    std::optional<std::array<double, 3>> color;  ///< the fabric's display colour, sRGB in 0..1
};

/// The per-particle fields of a drape (analysis/vertex_fields.hpp), its residual forces those the
/// solver measures (sim::residual_forces) with the drape's contact distance and friction.
analysis::VertexFields drape_vertex_fields(const DrapeMeshes& d);

/// Adds drape.obj, drape.ply (the grid; not for a cut cloth) and drape.glb (the cloth and the
/// obstacles, gltf_file.hpp) to `set`. RuntimeError when a field is not finite (nothing is added
/// then but what was before it; the set is not published).
void add_drape_meshes(OutputSet& set, const DrapeMeshes& d);

/// A GLB of a draped surface (the Cusick specimen) over the obstacles, its cloth lifted off them
/// for display as drape.glb's (geometry/display_surface.hpp), with texture coordinates.
std::string draped_surface_glb(const geometry::TriangleMesh& surface, const std::vector<Vec2>& uv,
                               const geometry::ObstacleSet& obstacles, double contact_distance,
                               const std::optional<std::array<double, 3>>& color);

}  // namespace woven::io
