// drape.glb (render/gltf_file.hpp) read back by tinygltf's own loader.
#include <cmath>
#include <cstring>
#include <memory>
#include <sstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include "woven/common/error.hpp"
#include "woven/geometry/primitives.hpp"
#include "woven/geometry/mesh_ops.hpp"
#include "woven/render/gltf_file.hpp"

#include "io/grid_fixture.hpp"

using namespace woven;
using ::testing::HasSubstr;

namespace {

using woven::test::fields;
using woven::test::grid;
using woven::test::kNu;
using woven::test::kNv;

tinygltf::Model load(const std::string& glb)
{
    tinygltf::Model m;
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    const bool ok = loader.LoadBinaryFromMemory(&m, &err, &warn, reinterpret_cast<const unsigned char*>(glb.data()),
                                                static_cast<unsigned int>(glb.size()));
    EXPECT_TRUE(ok) << err;
    EXPECT_TRUE(err.empty()) << err;
    EXPECT_TRUE(warn.empty()) << warn;
    return m;
}

/// The floats of an accessor (tightly packed float data, as the writer writes it).
std::vector<float> floats(const tinygltf::Model& m, int accessor)
{
    const auto& a = m.accessors.at(accessor);
    EXPECT_EQ(a.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
    const auto& v = m.bufferViews.at(a.bufferView);
    const int width = a.type == TINYGLTF_TYPE_VEC3 ? 3 : a.type == TINYGLTF_TYPE_VEC2 ? 2 : 1;
    std::vector<float> out(a.count * width);
    std::memcpy(out.data(), m.buffers.at(v.buffer).data.data() + v.byteOffset + a.byteOffset, out.size() * sizeof(float));
    return out;
}

}  // namespace

TEST(Gltf, ClothAndObstaclesRoundTripThroughTinygltfsLoader)
{
    const Positions x = grid();
    geometry::ObstacleSet obstacles;
    obstacles.add(std::make_unique<geometry::Sphere>(Vec3(0.2, -0.1, 0.2), 0.1));
    obstacles.add(std::make_unique<geometry::Plane>(Vec3(0, 0, 0), Vec3(0, 0, 1), 2.0));
    std::vector<render::GltfMesh> meshes{render::cloth_gltf_mesh(x, kNu, kNv, fields())};
    for (auto& o : render::obstacle_gltf_meshes(obstacles)) meshes.push_back(std::move(o));
    const std::string glb = render::scene_glb(meshes);
    ASSERT_EQ(glb.substr(0, 4), "glTF");
    const tinygltf::Model m = load(glb);
    EXPECT_EQ(m.asset.version, "2.0");
    ASSERT_EQ(m.scenes.size(), 1u);
    ASSERT_EQ(m.scenes[0].nodes.size(), 3u);
    EXPECT_EQ(m.nodes[0].name, "cloth");
    EXPECT_EQ(m.nodes[1].name, "obstacle 0 sphere");
    EXPECT_EQ(m.nodes[2].name, "obstacle 1 plane");

    const auto& cloth = m.meshes.at(m.nodes[0].mesh).primitives.at(0);
    for (const char* a : {"POSITION", "NORMAL", "TEXCOORD_0", "_STRAIN_WARP", "_CONTACT"}) EXPECT_EQ(cloth.attributes.count(a), 1u) << a;
    const auto& pos_acc = m.accessors.at(cloth.attributes.at("POSITION"));
    ASSERT_EQ(pos_acc.count, static_cast<size_t>(kNu * kNv));
    EXPECT_EQ(m.accessors.at(cloth.indices).count, static_cast<size_t>(3 * 2 * (kNu - 1) * (kNv - 1)));
    // y-up: woven (x, y, z) is glTF (x, z, -y); the bounds the accessor states are the data's.
    const auto pos = floats(m, cloth.attributes.at("POSITION"));
    for (int p = 0; p < kNu * kNv; ++p) {
        EXPECT_FLOAT_EQ(pos[3 * p + 0], static_cast<float>(x[p].x()));
        EXPECT_FLOAT_EQ(pos[3 * p + 1], static_cast<float>(x[p].z()));
        EXPECT_FLOAT_EQ(pos[3 * p + 2], static_cast<float>(-x[p].y()));
    }
    // flat_grid centred at (0.2, -0.1): x in [0.05, 0.35], woven y in [-0.2, 0], z in [0.5, 0.53].
    ASSERT_EQ(pos_acc.minValues.size(), 3u);
    EXPECT_NEAR(pos_acc.minValues[0], 0.05, 1e-7);
    EXPECT_NEAR(pos_acc.maxValues[0], 0.35, 1e-7);
    EXPECT_NEAR(pos_acc.minValues[1], 0.5, 1e-7);
    EXPECT_NEAR(pos_acc.maxValues[1], 0.53, 1e-7);
    EXPECT_NEAR(pos_acc.minValues[2], 0.0, 1e-7);
    EXPECT_NEAR(pos_acc.maxValues[2], 0.2, 1e-7);
    // Normals: the grid's vertex normals, turned as the positions (the far corner's, away from the lifted
    // particle, is +z: glTF's +y).
    const auto nrm = floats(m, cloth.attributes.at("NORMAL"));
    const Positions n = geometry::vertex_normals(geometry::grid_mesh(x, kNu, kNv));
    for (int p = 0; p < kNu * kNv; ++p) {
        EXPECT_FLOAT_EQ(nrm[3 * p + 0], static_cast<float>(n[p].x()));
        EXPECT_FLOAT_EQ(nrm[3 * p + 1], static_cast<float>(n[p].z()));
        EXPECT_FLOAT_EQ(nrm[3 * p + 2], static_cast<float>(-n[p].y()));
    }
    EXPECT_FLOAT_EQ(nrm[3 * (kNu * kNv - 1) + 1], 1.0f);
    // Texture coordinates: (u, 1 - v), u along the weft (i), v along the warp (j).
    const auto uv = floats(m, cloth.attributes.at("TEXCOORD_0"));
    EXPECT_FLOAT_EQ(uv[2 * (kNu - 1) + 0], 1.0f);
    EXPECT_FLOAT_EQ(uv[2 * (kNu - 1) + 1], 1.0f);
    EXPECT_FLOAT_EQ(uv[2 * (kNu * kNv - 1) + 1], 0.0f);
    // The fields, value by value.
    const auto f = fields();
    const auto strain = floats(m, cloth.attributes.at("_STRAIN_WARP"));
    const auto contact = floats(m, cloth.attributes.at("_CONTACT"));
    for (int p = 0; p < kNu * kNv; ++p) {
        EXPECT_FLOAT_EQ(strain[p], static_cast<float>(f[0].values[p]));
        EXPECT_FLOAT_EQ(contact[p], static_cast<float>(f[1].values[p]));
    }
    EXPECT_TRUE(m.asset.extras.Get("units").Get("_STRAIN_WARP").IsString());
    // The sphere: its tessellation's bounds, within its radius of its centre (y-up).
    const auto& sphere = m.meshes.at(m.nodes[1].mesh).primitives.at(0);
    const auto& sa = m.accessors.at(sphere.attributes.at("POSITION"));
    EXPECT_NEAR(sa.maxValues[1], 0.3, 1e-6);
    EXPECT_NEAR(sa.minValues[1], 0.1, 1e-6);
    EXPECT_EQ(sphere.attributes.count("_STRAIN_WARP"), 0u);
}

TEST(Gltf, MismatchedArraysAreRefused)
{
    auto bad = fields();
    bad[0].values.pop_back();
    EXPECT_THROW(render::scene_glb({render::cloth_gltf_mesh(grid(), kNu, kNv, bad)}), InputError);
    render::GltfMesh m = render::cloth_gltf_mesh(grid(), kNu, kNv);
    m.mesh.faces[0][1] = kNu * kNv;  // past the vertices
    EXPECT_THROW(render::scene_glb({m}), InputError);
    EXPECT_THROW(render::cloth_gltf_mesh(grid(), kNu + 1, kNv), InputError);
    EXPECT_EQ(render::gltf_attribute("trellis_angle"), "_TRELLIS_ANGLE");
}

TEST(Gltf, CheckGlbReadsWhatTheWriterWritesAndRefusesTheRest)
{
    const std::string glb = render::scene_glb({render::cloth_gltf_mesh(grid(), kNu, kNv, fields())});
    EXPECT_EQ(render::check_glb(glb, "d/drape.glb"), 1);
    for (const std::string& bad : {glb.substr(0, glb.size() / 2), std::string("glTF"), std::string()}) {
        try {
            render::check_glb(bad, "d/drape.glb");
            ADD_FAILURE() << "accepted " << bad.size() << " bytes";
        } catch (const InputError& e) {
            EXPECT_EQ(std::string(e.what()).rfind("d/drape.glb: glb: does not load as glTF 2.0 binary", 0), 0u) << e.what();
        }
    }
}
