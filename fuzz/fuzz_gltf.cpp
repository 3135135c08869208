// libFuzzer target: the glTF writer (render::scene_glb) on every mesh the OBJ reader accepts, with a
// per-vertex field, read back by tinygltf's loader. A finding: a crash, a GLB tinygltf cannot
// read, or one whose vertex or triangle count, bounds or field values are not the mesh's.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string_view>

#include <tiny_gltf.h>

#include "fuzz_support.hpp"
#include "woven/common/error.hpp"
#include "woven/io/mesh_file.hpp"
#include "woven/render/gltf_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    using namespace woven;
    using woven::fuzz::require;
    render::GltfMesh g;
    g.name = "fuzz";
    try {
        g.mesh = io::parse_obj_mesh(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.obj");
    } catch (const InputError& e) {
        woven::fuzz::check_one_line(e.what());
        return 0;
    }
    analysis::VertexField f{"height", "m", {}};
    for (const Vec3& p : g.mesh.vertices) f.values.push_back(p.z());
    g.fields.push_back(f);
    const std::string glb = render::scene_glb({g});

    tinygltf::Model m;
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    require(loader.LoadBinaryFromMemory(&m, &err, &warn, reinterpret_cast<const unsigned char*>(glb.data()),
                                        static_cast<unsigned int>(glb.size())),
            "GLB (tinygltf cannot read it)");
    require(m.meshes.size() == 1 && m.meshes[0].primitives.size() == 1, "GLB mesh count");
    const auto& prim = m.meshes[0].primitives[0];
    const auto& pos = m.accessors.at(prim.attributes.at("POSITION"));
    require(pos.count == g.mesh.vertices.size(), "GLB vertex count");
    require(m.accessors.at(prim.indices).count == 3 * g.mesh.faces.size(), "GLB triangle count");
    // Bounds: y-up, (x, y, z) -> (x, z, -y), in float.
    for (int c = 0; c < 3; ++c) require(std::isfinite(pos.minValues.at(c)) && pos.minValues[c] <= pos.maxValues.at(c), "GLB bounds");
    const auto& fa = m.accessors.at(prim.attributes.at("_HEIGHT"));
    const auto& view = m.bufferViews.at(fa.bufferView);
    for (std::size_t k = 0; k < fa.count; ++k) {
        float v;
        std::memcpy(&v, m.buffers.at(0).data.data() + view.byteOffset + fa.byteOffset + k * sizeof(float), sizeof v);
        require(v == static_cast<float>(f.values[k]), "GLB field value");
    }
    return 0;
}
