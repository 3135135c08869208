#include "woven/io/mesh_file.hpp"

#include <cmath>
#include <filesystem>
#include <sstream>

#include <tiny_obj_loader.h>

#include "woven/common/error.hpp"

namespace woven::io {

namespace {

/// Gathers all shapes of a parsed OBJ into one mesh, checking indices and coordinates.
geometry::TriangleMesh to_mesh(const tinyobj::ObjReader& reader, const std::string& source)
{
    const auto& attrib = reader.GetAttrib();
    const auto nv = static_cast<long long>(attrib.vertices.size() / 3);
    geometry::TriangleMesh mesh;
    mesh.vertices.reserve(nv);
    for (long long k = 0; k < nv; ++k) {
        const Vec3 p(attrib.vertices[3 * k], attrib.vertices[3 * k + 1], attrib.vertices[3 * k + 2]);
        if (!p.allFinite())
            throw InputError(source, "vertices", "vertex " + std::to_string(k + 1) + " is not finite");
        mesh.vertices.push_back(p);
    }
    for (const auto& shape : reader.GetShapes()) {
        size_t offset = 0;
        for (size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
            const int n = shape.mesh.num_face_vertices[f];
            if (n != 3) throw InputError(source, "faces", "face with " + std::to_string(n) + " vertices after triangulation");
            Eigen::Vector3i face;
            for (int c = 0; c < 3; ++c) {
                const int v = shape.mesh.indices[offset + c].vertex_index;
                if (v < 0 || v >= nv)
                    throw InputError(source, "faces",
                                     "vertex index out of range in shape '" + shape.name + "' (" + std::to_string(nv) +
                                         " vertices)");
                face[c] = v;
            }
            offset += 3;
            if (face[0] == face[1] || face[1] == face[2] || face[0] == face[2]) continue;  // degenerate
            mesh.faces.push_back(face);
        }
    }
    if (mesh.faces.empty()) throw InputError(source, "faces", "the OBJ file has no faces");
    return mesh;
}

tinyobj::ObjReaderConfig reader_config()
{
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    return config;
}

std::string first_line(const std::string& s)
{
    std::string t = s.substr(0, s.find('\n'));
    return t.empty() ? std::string("cannot parse") : t;
}

}  // namespace

geometry::TriangleMesh load_obj_mesh(const std::string& path)
{
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path, "file", "no such mesh file");
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(path, reader_config())) throw InputError(path, "file", first_line(reader.Error()));
    return to_mesh(reader, path);
}

geometry::TriangleMesh parse_obj_mesh(std::string_view text, const std::string& source)
{
    tinyobj::ObjReader reader;
    if (!reader.ParseFromString(std::string(text), std::string(), reader_config()))
        throw InputError(source, "file", first_line(reader.Error()));
    return to_mesh(reader, source);
}

}  // namespace woven::io
