#pragma once
// glTF 2.0 binary (.glb) output through tinygltf (Debian's libtinygltf-dev): the draped cloth
// and the obstacles, for any glTF viewer (Blender, three.js, f3d).
//
// Axes: woven's scenes are z-up, glTF is y-up (glTF 2.0 spec, 3.4 "Coordinate System and
// Units"). A woven point (x, y, z) is written as (x, z, -y): a rotation of -90 degrees about x,
// so lengths, handedness and the triangles' winding are kept; metres throughout. glTF's
// texture origin is the top left: woven's (u, v) is written as (u, 1 - v).
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "woven/analysis/vertex_fields.hpp"
#include "woven/common/types.hpp"
#include "woven/geometry/obstacle.hpp"
#include "woven/geometry/triangle_mesh.hpp"

namespace woven::render {

/// One mesh of the scene, in woven's axes (m).
struct GltfMesh {
    std::string name;
    geometry::TriangleMesh mesh;
    Positions normals;              ///< one per vertex, or empty (viewers then shade flat)
    std::vector<Vec2> uv;           ///< one per vertex, or empty
    std::vector<analysis::VertexField> fields;  ///< one value per vertex each: custom attributes
    std::array<double, 3> color{0.6, 0.6, 0.6};  ///< base colour, linear RGB in 0..1
    bool double_sided = false;
    std::string holds;  ///< what the mesh is, for a reader (the node's extras "holds"); may be empty
};

/// The glTF attribute of a per-vertex field: "_" + the name in upper case ("_STRAIN_WARP";
/// application-specific attributes start with "_", glTF 2.0 spec 3.7.2.1).
std::string gltf_attribute(const std::string& field_name);

/// The meshes as one binary glTF (GLB): one node per mesh, named as it, in one scene; each a
/// triangle primitive with POSITION (float, with its bounds), NORMAL and TEXCOORD_0 where given,
/// the fields as float scalar attributes, uint32 indices and a metallic-roughness material.
/// The asset's "extras" give the axis conversion and each field's unit. Throws InputError when
/// an array's length does not match the vertices or a face indexes past them.
std::string scene_glb(const std::vector<GltfMesh>& meshes);

/// Reads a GLB back with tinygltf's loader: InputError "<source>: glb: <what>" when it does not
/// load, has no mesh, or a POSITION accessor whose bounds are missing or not finite. Returns the
/// number of meshes.
int check_glb(std::string_view data, const std::string& source);

/// The cloth grid (nu x nv, triangles and (u, v) as io::cloth_obj's) with its vertex normals, and
/// `fields` (one value per particle each).
GltfMesh cloth_gltf_mesh(const Positions& x, int nu, int nv, const std::vector<analysis::VertexField>& fields = {});

/// The obstacles, tessellated, named "obstacle <k> <kind>" (k from 0 in the set's order).
std::vector<GltfMesh> obstacle_gltf_meshes(const geometry::ObstacleSet& obstacles);

/// A surface that is not the particle grid (a cloth cut to its outline, the Cusick specimen):
/// named "cloth", with texture coordinates, double-sided.
GltfMesh surface_gltf_mesh(const geometry::TriangleMesh& surface, const std::vector<Vec2>& uv);

/// The GLB a viewer is given: `cloth` lifted off the obstacles by the contact distance
/// (geometry/display_surface.hpp) so that no obstacle's edge shows through its flat triangles,
/// in the fabric's colour (sRGB in 0..1) when one is given, then the obstacles. The cloth node's
/// "holds" says so: `lifted` names what was lifted ("the cloth's vertices"), `solved_in` which
/// files hold it as solved.
std::string display_glb(GltfMesh cloth, const geometry::ObstacleSet& obstacles, double contact_distance,
                        const std::optional<std::array<double, 3>>& color, const std::string& lifted, const std::string& solved_in);

}  // namespace woven::render
