// libFuzzer target: `woven check`'s glb reader (render::check_glb) on any bytes. Bad input must be
// a one-line InputError. An accepted file is read again as a viewer reads it, independently of
// the checker: every primitive's index and attribute data within its buffer (ASan sees a read
// past it), every index naming a vertex, every position finite: anything else is a finding.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include <tiny_gltf.h>

#include "fuzz_support.hpp"
#include "woven/common/error.hpp"
#include "woven/render/gltf_file.hpp"

namespace {

/// Element `e`, component `c` of accessor `a` as a double, read straight from its buffer.
double element(const tinygltf::Model& m, const tinygltf::Accessor& a, std::size_t e, int c)
{
    const auto& v = m.bufferViews.at(static_cast<std::size_t>(a.bufferView));
    const auto& b = m.buffers.at(static_cast<std::size_t>(v.buffer)).data;
    const int size = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(a.componentType));
    const int n = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
    const std::size_t stride = v.byteStride ? v.byteStride : static_cast<std::size_t>(size * n);
    const std::size_t at = v.byteOffset + a.byteOffset + e * stride + static_cast<std::size_t>(c * size);
    woven::fuzz::require(at + static_cast<std::size_t>(size) <= v.byteOffset + v.byteLength && at + static_cast<std::size_t>(size) <= b.size(),
                         "glb (an accessor reads past its buffer view)");
    const unsigned char* p = b.data() + at;
    switch (a.componentType) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: { float f; std::memcpy(&f, p, 4); return f; }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t u; std::memcpy(&u, p, 4); return u; }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t u; std::memcpy(&u, p, 2); return u; }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
    default: { double d = 0; std::memcpy(&d, p, std::min(size, 8)); return d; }
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    using namespace woven;
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    try {
        (void)render::check_glb(bytes, "fuzz.glb");
    } catch (const InputError& e) {
        woven::fuzz::check_one_line(e.what());
        return 0;
    }
    tinygltf::Model m;
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    woven::fuzz::require(loader.LoadBinaryFromMemory(&m, &err, &warn, data, static_cast<unsigned int>(size)), "glb (does not load again)");
    for (const auto& mesh : m.meshes)
        for (const auto& prim : mesh.primitives) {
            const auto& pos = m.accessors.at(static_cast<std::size_t>(prim.attributes.at("POSITION")));
            for (std::size_t e = 0; e < pos.count; ++e)
                for (int c = 0; c < 3; ++c) woven::fuzz::require(std::isfinite(element(m, pos, e, c)), "glb position");
            for (const auto& [name, index] : prim.attributes) {
                const auto& a = m.accessors.at(static_cast<std::size_t>(index));
                woven::fuzz::require(a.count == pos.count, "glb attribute length");
                for (std::size_t e = 0; e < a.count; ++e) (void)element(m, a, e, 0);
            }
            if (prim.indices >= 0) {
                const auto& ia = m.accessors.at(static_cast<std::size_t>(prim.indices));
                woven::fuzz::require(ia.count % 3 == 0, "glb triangles");
                for (std::size_t e = 0; e < ia.count; ++e) woven::fuzz::require(element(m, ia, e, 0) < static_cast<double>(pos.count), "glb index");
            }
        }
    return 0;
}
