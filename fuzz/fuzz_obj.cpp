// libFuzzer target: the OBJ reader (io::parse_obj_mesh). Bad input must be an InputError; an
// accepted mesh must have finite vertices and faces indexing them.
#include <cmath>
#include <cstdint>
#include <string_view>

#include "fuzz_support.hpp"
#include "woven/common/error.hpp"
#include "woven/io/mesh_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    using namespace woven;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    geometry::TriangleMesh mesh;
    try {
        mesh = io::parse_obj_mesh(text, "fuzz.obj");
    } catch (const InputError& e) {
        woven::fuzz::check_one_line(e.what());
        return 0;
    }
    woven::fuzz::require(!mesh.faces.empty(), "mesh (no faces)");
    for (const Vec3& p : mesh.vertices) woven::fuzz::require(p.allFinite(), "vertex");
    const int nv = static_cast<int>(mesh.vertices.size());
    for (const auto& f : mesh.faces)
        for (int c = 0; c < 3; ++c) woven::fuzz::require(f[c] >= 0 && f[c] < nv, "face index");
    return 0;
}
