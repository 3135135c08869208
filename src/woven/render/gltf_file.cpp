#include "woven/render/gltf_file.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <sstream>

#include <tiny_gltf.h>

#include "woven/common/error.hpp"
#include "woven/geometry/display_surface.hpp"
#include "woven/geometry/mesh_ops.hpp"

namespace woven::render {

namespace {

/// woven's z-up (x, y, z) as glTF's y-up (x, z, -y) (the header's rotation).
std::array<float, 3> to_gltf(const Vec3& p)
{
    return {static_cast<float>(p.x()), static_cast<float>(p.z()), static_cast<float>(-p.y())};
}

/// Appends raw little-endian data to the buffer, 4-byte aligned, and adds a view of it.
int add_view(tinygltf::Model& m, const void* data, std::size_t bytes, int target)
{
    auto& buf = m.buffers[0].data;
    buf.resize((buf.size() + 3) / 4 * 4, 0);
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = buf.size();
    v.byteLength = bytes;
    v.target = target;
    const auto* p = static_cast<const unsigned char*>(data);
    buf.insert(buf.end(), p, p + bytes);
    m.bufferViews.push_back(v);
    return static_cast<int>(m.bufferViews.size()) - 1;
}

int add_accessor(tinygltf::Model& m, int view, int component, int type, std::size_t count, std::vector<double> min = {},
                 std::vector<double> max = {})
{
    tinygltf::Accessor a;
    a.bufferView = view;
    a.byteOffset = 0;
    a.componentType = component;
    a.type = type;
    a.count = count;
    a.minValues = std::move(min);
    a.maxValues = std::move(max);
    m.accessors.push_back(a);
    return static_cast<int>(m.accessors.size()) - 1;
}

int add_floats(tinygltf::Model& m, const std::vector<float>& v, int type, int width, bool bounds)
{
    std::vector<double> lo, hi;
    if (bounds) {
        lo.assign(width, std::numeric_limits<double>::infinity());
        hi.assign(width, -std::numeric_limits<double>::infinity());
        for (std::size_t k = 0; k < v.size(); ++k) {
            lo[k % width] = std::min<double>(lo[k % width], v[k]);
            hi[k % width] = std::max<double>(hi[k % width], v[k]);
        }
    }
    const int view = add_view(m, v.data(), v.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
    return add_accessor(m, view, TINYGLTF_COMPONENT_TYPE_FLOAT, type, v.size() / width, lo, hi);
}

void check_length(std::size_t n, std::size_t vertices, const std::string& mesh, const std::string& what)
{
    if (n != 0 && n != vertices)
        throw InputError("glTF output", mesh + "." + what,
                         std::to_string(n) + " values for " + std::to_string(vertices) + " vertices");
}

}  // namespace

std::string gltf_attribute(const std::string& field_name)
{
    std::string s = "_" + field_name;
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
    return s;
}

std::string scene_glb(const std::vector<GltfMesh>& meshes)
{
    tinygltf::Model m;
    m.asset.version = "2.0";
    m.asset.generator = std::string("woven ") + WOVEN_VERSION;
    tinygltf::Value::Object extras;
    extras["axes"] = tinygltf::Value(std::string("woven (x, y, z) z-up is written as glTF (x, z, -y) y-up; metres"));
    tinygltf::Value::Object units;
    m.buffers.emplace_back();
    tinygltf::Scene scene;
    scene.name = "woven";
    for (const GltfMesh& g : meshes) {
        const std::size_t n = g.mesh.vertices.size();
        check_length(g.normals.size(), n, g.name, "normals");
        check_length(g.uv.size(), n, g.name, "uv");
        for (const auto& f : g.fields) {
            if (f.values.size() != n)
                throw InputError("glTF output", g.name + "." + f.name,
                                 std::to_string(f.values.size()) + " values for " + std::to_string(n) + " vertices");
            units[gltf_attribute(f.name)] = tinygltf::Value(f.unit);
        }
        if (n == 0 || g.mesh.faces.empty()) throw InputError("glTF output", g.name, "a mesh needs vertices and faces");
        tinygltf::Primitive prim;
        prim.mode = TINYGLTF_MODE_TRIANGLES;
        std::vector<float> pos;
        pos.reserve(3 * n);
        for (const Vec3& p : g.mesh.vertices)
            for (float c : to_gltf(p)) pos.push_back(c);
        prim.attributes["POSITION"] = add_floats(m, pos, TINYGLTF_TYPE_VEC3, 3, true);  // bounds: required
        if (!g.normals.empty()) {
            std::vector<float> nrm;
            nrm.reserve(3 * n);
            for (const Vec3& p : g.normals)
                for (float c : to_gltf(p)) nrm.push_back(c);
            prim.attributes["NORMAL"] = add_floats(m, nrm, TINYGLTF_TYPE_VEC3, 3, false);
        }
        if (!g.uv.empty()) {
            std::vector<float> uv;
            uv.reserve(2 * n);
            for (const Vec2& t : g.uv) {
                uv.push_back(static_cast<float>(t.x()));
                uv.push_back(static_cast<float>(1.0 - t.y()));
            }
            prim.attributes["TEXCOORD_0"] = add_floats(m, uv, TINYGLTF_TYPE_VEC2, 2, false);
        }
        for (const auto& f : g.fields) {
            std::vector<float> v(f.values.begin(), f.values.end());
            prim.attributes[gltf_attribute(f.name)] = add_floats(m, v, TINYGLTF_TYPE_SCALAR, 1, true);
        }
        std::vector<std::uint32_t> idx;
        idx.reserve(3 * g.mesh.faces.size());
        for (const auto& f : g.mesh.faces)
            for (int c = 0; c < 3; ++c) {
                if (f[c] < 0 || static_cast<std::size_t>(f[c]) >= n)
                    throw InputError("glTF output", g.name + ".faces", "index " + std::to_string(f[c]) + " past the vertices");
                idx.push_back(static_cast<std::uint32_t>(f[c]));
            }
        const int iview = add_view(m, idx.data(), idx.size() * sizeof(std::uint32_t), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
        prim.indices = add_accessor(m, iview, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, idx.size());

        tinygltf::Material mat;
        mat.name = g.name;
        mat.pbrMetallicRoughness.baseColorFactor = {g.color[0], g.color[1], g.color[2], 1.0};
        mat.pbrMetallicRoughness.metallicFactor = 0.0;
        mat.pbrMetallicRoughness.roughnessFactor = 0.9;
        mat.doubleSided = g.double_sided;
        m.materials.push_back(mat);
        prim.material = static_cast<int>(m.materials.size()) - 1;

        tinygltf::Mesh mesh;
        mesh.name = g.name;
        mesh.primitives.push_back(prim);
        m.meshes.push_back(mesh);
        tinygltf::Node node;
        node.name = g.name;
        node.mesh = static_cast<int>(m.meshes.size()) - 1;
        if (!g.holds.empty()) {
            tinygltf::Value::Object node_extras;
            node_extras["holds"] = tinygltf::Value(g.holds);
            node.extras = tinygltf::Value(node_extras);
        }
        m.nodes.push_back(node);
        scene.nodes.push_back(static_cast<int>(m.nodes.size()) - 1);
    }
    m.buffers[0].data.resize((m.buffers[0].data.size() + 3) / 4 * 4, 0);
    extras["units"] = tinygltf::Value(units);
    m.asset.extras = tinygltf::Value(extras);
    m.scenes.push_back(scene);
    m.defaultScene = 0;
    std::ostringstream out;
    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToStream(&m, out, false, true)) throw RuntimeError("glTF output: tinygltf could not write the scene");
    return out.str();
}

namespace {

/// One accessor's elements as a viewer reads them, each component as a double; InputError
/// naming `what` when the accessor, its buffer view or its buffer do not hold them.
std::vector<double> accessor_values(const tinygltf::Model& m, int index, const std::string& source, const std::string& what,
                                    int* components_out)
{
    const auto fail = [&](const std::string& why) { throw InputError(source, "glb", what + ": " + why); };
    if (index < 0 || index >= static_cast<int>(m.accessors.size())) fail("no such accessor " + std::to_string(index));
    const tinygltf::Accessor& a = m.accessors[static_cast<std::size_t>(index)];
    if (a.sparse.isSparse) fail("a sparse accessor (expected plain data)");
    const int components = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
    const int size = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(a.componentType));
    if (components <= 0 || components > 16 || size <= 0) fail("an unknown accessor type or component type");
    if (a.count == 0 || a.count > (1u << 30)) fail("expected 1 .. 2^30 elements, got " + std::to_string(a.count));
    if (a.bufferView < 0 || a.bufferView >= static_cast<int>(m.bufferViews.size())) fail("no buffer view");
    const tinygltf::BufferView& v = m.bufferViews[static_cast<std::size_t>(a.bufferView)];
    if (v.buffer < 0 || v.buffer >= static_cast<int>(m.buffers.size())) fail("its buffer view names no buffer");
    const std::vector<unsigned char>& b = m.buffers[static_cast<std::size_t>(v.buffer)].data;
    if (v.byteOffset > b.size() || v.byteLength > b.size() - v.byteOffset)
        fail("its buffer view (" + std::to_string(v.byteOffset) + " + " + std::to_string(v.byteLength) + " bytes) runs past its buffer (" +
             std::to_string(b.size()) + " bytes)");
    const std::size_t element = static_cast<std::size_t>(components) * static_cast<std::size_t>(size);
    const std::size_t stride = v.byteStride == 0 ? element : v.byteStride;
    if (stride < element) fail("a stride smaller than an element");
    if (a.byteOffset > v.byteLength || (a.count - 1) > (v.byteLength - a.byteOffset) / stride ||
        a.byteOffset + (a.count - 1) * stride + element > v.byteLength)
        fail(std::to_string(a.count) + " elements run past the buffer view (" + std::to_string(v.byteLength) + " bytes)");
    if (a.byteOffset % static_cast<std::size_t>(size) != 0 || (v.byteOffset % static_cast<std::size_t>(size)) != 0)
        fail("data not aligned to its component size");
    std::vector<double> out;
    out.reserve(a.count * static_cast<std::size_t>(components));
    const unsigned char* base = b.data() + v.byteOffset + a.byteOffset;
    for (std::size_t e = 0; e < a.count; ++e)
        for (int c = 0; c < components; ++c) {
            const unsigned char* p = base + e * stride + static_cast<std::size_t>(c) * static_cast<std::size_t>(size);
            double x = 0;
            switch (a.componentType) {
            case TINYGLTF_COMPONENT_TYPE_FLOAT: { float f; std::memcpy(&f, p, 4); x = f; break; }
            case TINYGLTF_COMPONENT_TYPE_DOUBLE: { double d; std::memcpy(&d, p, 8); x = d; break; }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t u; std::memcpy(&u, p, 4); x = u; break; }
            case TINYGLTF_COMPONENT_TYPE_INT: { int32_t i; std::memcpy(&i, p, 4); x = i; break; }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t u; std::memcpy(&u, p, 2); x = u; break; }
            case TINYGLTF_COMPONENT_TYPE_SHORT: { int16_t i; std::memcpy(&i, p, 2); x = i; break; }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: x = *p; break;
            case TINYGLTF_COMPONENT_TYPE_BYTE: x = static_cast<signed char>(*p); break;
            default: fail("an unknown component type");
            }
            out.push_back(x);
        }
    *components_out = components;
    return out;
}

}  // namespace

int check_glb(std::string_view data, const std::string& source)
{
    tinygltf::Model m;
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    if (data.size() > std::numeric_limits<unsigned int>::max())
        throw InputError(source, "glb", "expected a glTF 2.0 binary of less than 4 GiB");
    if (!loader.LoadBinaryFromMemory(&m, &err, &warn, reinterpret_cast<const unsigned char*>(data.data()),
                                     static_cast<unsigned int>(data.size())))
        // tinygltf's message may span lines (a JSON parse error quotes the parser's): one line.
        throw InputError(source, "glb", "does not load as glTF 2.0 binary (" + printable(err.empty() ? std::string("tinygltf") : err, 200) + ")");
    if (m.meshes.empty()) throw InputError(source, "glb", "has no mesh");
    // What a viewer reads of each primitive: every accessor within its buffer view and buffer,
    // positions finite and within the accessor's bounds, every other float attribute finite,
    // the attributes of one length, every index naming a vertex, whole triangles.
    for (const auto& mesh : m.meshes) {
        const std::string name = "mesh '" + printable(mesh.name) + "'";
        if (mesh.primitives.empty()) throw InputError(source, "glb", name + ": has no primitive");
        for (std::size_t k = 0; k < mesh.primitives.size(); ++k) {
            const auto& prim = mesh.primitives[k];
            const std::string pname = name + " primitive " + std::to_string(k);
            const auto it = prim.attributes.find("POSITION");
            if (it == prim.attributes.end() || it->second < 0 || it->second >= static_cast<int>(m.accessors.size()))
                throw InputError(source, "glb", "mesh '" + printable(mesh.name) + "' has no POSITION");
            const auto& a = m.accessors[static_cast<std::size_t>(it->second)];
            bool finite = a.minValues.size() == 3 && a.maxValues.size() == 3;
            for (std::size_t c = 0; finite && c < 3; ++c) finite = std::isfinite(a.minValues[c]) && std::isfinite(a.maxValues[c]);
            if (!finite) throw InputError(source, "glb", "mesh '" + printable(mesh.name) + "': POSITION bounds missing or not finite");
            if (a.type != TINYGLTF_TYPE_VEC3 || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
                throw InputError(source, "glb", pname + ": POSITION: expected 3 floats per vertex");
            std::size_t vertices = a.count;
            for (const auto& [attr, index] : prim.attributes) {
                int components = 0;
                const std::vector<double> x = accessor_values(m, index, source, pname + ": " + printable(attr), &components);
                if (m.accessors[static_cast<std::size_t>(index)].count != vertices)
                    throw InputError(source, "glb", pname + ": " + printable(attr) + ": " +
                                                        std::to_string(m.accessors[static_cast<std::size_t>(index)].count) +
                                                        " elements, POSITION has " + std::to_string(vertices));
                for (std::size_t i = 0; i < x.size(); ++i) {
                    if (!std::isfinite(x[i]))
                        throw InputError(source, "glb", pname + ": " + printable(attr) + ": element " + std::to_string(i / components) +
                                                            " is not a finite number");
                    if (attr == "POSITION") {
                        const std::size_t c = i % 3;
                        const double tol = 1e-6 * std::max({1.0, std::abs(a.minValues[c]), std::abs(a.maxValues[c])});
                        if (x[i] < a.minValues[c] - tol || x[i] > a.maxValues[c] + tol)
                            throw InputError(source, "glb", pname + ": POSITION: vertex " + std::to_string(i / 3) +
                                                                " lies outside the accessor's min/max");
                    }
                }
            }
            const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
            if (mode != TINYGLTF_MODE_TRIANGLES) throw InputError(source, "glb", pname + ": expected triangles (mode 4), got mode " + std::to_string(mode));
            if (prim.indices >= 0) {
                if (static_cast<std::size_t>(prim.indices) >= m.accessors.size())
                    throw InputError(source, "glb", pname + ": indices: no such accessor");
                const auto& ia = m.accessors[static_cast<std::size_t>(prim.indices)];
                if (ia.type != TINYGLTF_TYPE_SCALAR ||
                    (ia.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT && ia.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                     ia.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE))
                    throw InputError(source, "glb", pname + ": indices: expected unsigned integers");
                int components = 0;
                const std::vector<double> idx = accessor_values(m, prim.indices, source, pname + ": indices", &components);
                if (idx.size() % 3 != 0) throw InputError(source, "glb", pname + ": indices: " + std::to_string(idx.size()) + " indices, not whole triangles");
                for (std::size_t i = 0; i < idx.size(); ++i)
                    if (idx[i] >= static_cast<double>(vertices))
                        throw InputError(source, "glb", pname + ": indices: index " + std::to_string(i) + " is " +
                                                            std::to_string(static_cast<unsigned long long>(idx[i])) + ", beyond the " +
                                                            std::to_string(vertices) + " vertices");
            } else if (vertices % 3 != 0) {
                throw InputError(source, "glb", pname + ": " + std::to_string(vertices) + " vertices without indices, not whole triangles");
            }
        }
    }
    return static_cast<int>(m.meshes.size());
}

GltfMesh cloth_gltf_mesh(const Positions& x, int nu, int nv, const std::vector<analysis::VertexField>& fields)
{
    GltfMesh g;
    g.name = "cloth";
    g.mesh = geometry::grid_mesh(x, nu, nv);
    g.normals = geometry::vertex_normals(g.mesh);
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) g.uv.emplace_back(double(i) / (nu - 1), double(j) / (nv - 1));
    g.fields = fields;
    g.color = {0.8, 0.75, 0.65};
    g.double_sided = true;
    return g;
}

std::vector<GltfMesh> obstacle_gltf_meshes(const geometry::ObstacleSet& obstacles)
{
    std::vector<GltfMesh> out;
    for (std::size_t k = 0; k < obstacles.size(); ++k) {
        GltfMesh g;
        g.name = "obstacle " + std::to_string(k) + " " + obstacles[k].kind();
        g.mesh = obstacles[k].tessellate();
        out.push_back(std::move(g));
    }
    return out;
}

GltfMesh surface_gltf_mesh(const geometry::TriangleMesh& surface, const std::vector<Vec2>& uv)
{
    GltfMesh g;
    g.name = "cloth";
    g.mesh = surface;
    g.uv = uv;
    g.double_sided = true;
    return g;
}

std::string display_glb(GltfMesh cloth, const geometry::ObstacleSet& obstacles, double contact_distance,
                        const std::optional<std::array<double, 3>>& color, const std::string& lifted, const std::string& solved_in)
{
    // sRGB (0..1) to linear RGB, glTF's baseColorFactor (IEC 61966-2-1).
    const auto linear = [](double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); };
    if (color)
        for (int c = 0; c < 3; ++c) cloth.color[c] = linear((*color)[c]);
    const geometry::LiftedSurface shown = geometry::lift_off_obstacles(cloth.mesh, obstacles, contact_distance);
    cloth.mesh = shown.mesh;
    char lift[160];
    std::snprintf(lift, sizeof lift, " (at most %.3g m) so that its triangles clear them by the contact distance %.3g m; ", shown.max_lift,
                  contact_distance);
    cloth.holds = "display surface: " + lifted + " lifted off the obstacles" + lift + solved_in;
    std::vector<GltfMesh> meshes{std::move(cloth)};
    for (auto& m : obstacle_gltf_meshes(obstacles)) meshes.push_back(std::move(m));
    return scene_glb(meshes);
}

}  // namespace woven::render
