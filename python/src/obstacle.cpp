// woven.Obstacle: an obstacle made in Python (a numpy mesh, a box, a sphere, ...), as the values of
// a scene's [[obstacle]] table, built and checked by the scene reader's own builder
// (io::obstacle_from_values); woven.Scene takes them in its obstacle list.
#include <filesystem>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "woven/geometry/triangle_mesh.hpp"
#include "woven/io/mesh_file.hpp"
#include "woven/io/values.hpp"

namespace woven::python {

namespace {

/// The keys given (None left out) as an obstacle's values, built once to check them.
Obstacle make(const std::string& type, py::dict keys)
{
    // A mesh's rows counted before they are converted (about 1 KB each on the way).
    if (type == "mesh")
        for (const char* key : {"vertices_m", "faces"})
            if (keys.contains(key) && py::hasattr(keys[key], "__len__")) {
                const auto n = static_cast<long long>(py::len(keys[key]));
                if (n > io::kMaxInlineMeshRows)
                    throw InputError(
                        kPythonObstacle, key,
                        "expected at most " + std::to_string(io::kMaxInlineMeshRows)
                            + " rows (about 1 KB each given as values; a larger mesh from a file: type = \"mesh\", file = ...), got "
                            + std::to_string(n));
            }
    py::dict d;
    d["type"] = type;
    for (auto [k, v] : keys)
        if (!v.is_none()) d[k] = v;
    Obstacle o;
    o.values = to_values(d, kPythonObstacle);
    std::vector<std::string> warnings;
    std::string kind;
    o.built = io::obstacle_from_values(o.values, kPythonObstacle, std::filesystem::current_path().string(), &kind, &warnings);
    o.kind = kind;
    warn(warnings);
    return o;
}

Obstacle from_dict(py::dict values)
{
    if (!values.contains("type")) throw InputError(kPythonObstacle, "type", "missing; expected plane, box, sphere, cylinder, disc or mesh");
    const std::string type = py::str(values["type"]);
    py::dict rest;
    for (auto [k, v] : values)
        if (py::str(k).cast<std::string>() != "type") rest[k] = v;
    return make(type, rest);
}

py::array_t<double> vertices_array(const geometry::TriangleMesh& m)
{
    py::array_t<double> a({static_cast<py::ssize_t>(m.vertices.size()), py::ssize_t(3)});
    auto r = a.mutable_unchecked<2>();
    for (std::size_t k = 0; k < m.vertices.size(); ++k)
        for (int c = 0; c < 3; ++c) r(k, c) = m.vertices[k][c];
    return a;
}

py::array_t<std::int32_t> faces_array(const geometry::TriangleMesh& m)
{
    py::array_t<std::int32_t> a({static_cast<py::ssize_t>(m.faces.size()), py::ssize_t(3)});
    auto r = a.mutable_unchecked<2>();
    for (std::size_t k = 0; k < m.faces.size(); ++k)
        for (int c = 0; c < 3; ++c) r(k, c) = m.faces[k][c];
    return a;
}

}  // namespace

void bind_obstacle(py::module_& m)
{
    py::class_<Obstacle>(m, "Obstacle", R"(An obstacle made in Python, for a scene's obstacle list.

Made by its constructors (lengths in m, angles in degrees, z up), each checked as the scene
file's [[obstacle]] table is (docs/SCENE-FORMAT.md), with its messages:

>>> import numpy as np, woven
>>> box = woven.Obstacle.box(centre_m=(0, 0, 0.25), size_m=(0.5, 0.5, 0.5))
>>> box.kind, box.bounds
('box', ((-0.25, -0.25, 0.0), (0.25, 0.25, 0.5)))
>>> tetra = woven.Obstacle.mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]]),
...                             np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]))
>>> tetra.vertices.shape, tetra.faces.shape
((4, 3), (4, 3))
>>> scene = woven.Scene(name="on a box", cloth={"size_m": [1, 1], "grid": [11, 11], "height_m": 0.51,
...                     "fabric": "cotton"}, obstacle=[woven.Obstacle.plane(), box])
>>> scene.obstacles
['plane', 'box']
>>> woven.drape(scene, grid=7, seed=1, threads=1).converged
True

Obstacle(values) takes the table as a dict ({"type": "sphere", "centre_m": ..., ...}). A bad
value raises woven.InputError naming "Python obstacle" and the key.)")
        .def(py::init(&from_dict), py::arg("values"))
        .def_static("mesh", [](py::object vertices, py::object faces, py::object scale, py::object rotation_deg, py::object translate_m) {
            py::dict k;
            k["vertices_m"] = vertices;
            k["faces"] = faces;
            k["scale"] = scale;
            k["rotation_deg"] = rotation_deg;
            k["translate_m"] = translate_m;
            return make("mesh", k);
        }, py::arg("vertices"), py::arg("faces"), py::kw_only(), py::arg("scale") = py::none(), py::arg("rotation_deg") = py::none(),
           py::arg("translate_m") = py::none(),
           "A triangle mesh: vertices (n, 3) in m and faces (m, 3) 0-based vertex indices, counter-clockwise seen from outside "
           "(a closed mesh is a solid, an open one a thin shell); scaled, rotated (x, y, z degrees) and translated as a scene's "
           "mesh obstacle.")
        .def_static("box", [](py::object centre_m, py::object size_m, py::object rotation_deg) {
            py::dict k;
            k["centre_m"] = centre_m;
            k["size_m"] = size_m;
            k["rotation_deg"] = rotation_deg;
            return make("box", k);
        }, py::arg("centre_m"), py::arg("size_m"), py::kw_only(), py::arg("rotation_deg") = py::none(),
           "A box: its centre and size (m), turned by rotation_deg about the vertical.")
        .def_static("sphere", [](py::object centre_m, py::object radius_m) {
            py::dict k;
            k["centre_m"] = centre_m;
            k["radius_m"] = radius_m;
            return make("sphere", k);
        }, py::arg("centre_m"), py::arg("radius_m"), "A sphere: its centre and radius (m).")
        .def_static("cylinder", [](py::object base_m, py::object radius_m, py::object height_m, py::object axis) {
            py::dict k;
            k["base_m"] = base_m;
            k["radius_m"] = radius_m;
            k["height_m"] = height_m;
            k["axis"] = axis;
            return make("cylinder", k);
        }, py::arg("base_m"), py::arg("radius_m"), py::arg("height_m"), py::kw_only(), py::arg("axis") = py::none(),
           "A solid cylinder from the centre of its base along axis (default +z).")
        .def_static("disc", [](py::object centre_m, py::object radius_m, py::object thickness_m) {
            py::dict k;
            k["centre_m"] = centre_m;
            k["radius_m"] = radius_m;
            k["thickness_m"] = thickness_m;
            return make("disc", k);
        }, py::arg("centre_m"), py::arg("radius_m"), py::kw_only(), py::arg("thickness_m") = py::none(),
           "A horizontal disc whose top face is centred at centre_m (the Cusick tester's support).")
        .def_static("plane", [](py::object point_m, py::object normal, py::object render_size_m) {
            py::dict k;
            k["point_m"] = point_m;
            k["normal"] = normal;
            k["render_size_m"] = render_size_m;
            return make("plane", k);
        }, py::arg("point_m") = py::none(), py::arg("normal") = py::none(), py::kw_only(), py::arg("render_size_m") = py::none(),
           "An infinite plane through point_m (default the origin) with the given normal (default +z): a floor.")
        .def_property_readonly("kind", [](const Obstacle& o) { return o.kind; }, "Its type: plane, box, sphere, cylinder, disc or mesh.")
        .def_property_readonly("values", [](const Obstacle& o) { return to_python(o.values); }, "The [[obstacle]] table it stands for, as a dict.")
        .def_property_readonly("bounds", [](const Obstacle& o) {
            const geometry::Aabb b = o.built->bounds();
            return py::make_tuple(py::make_tuple(b.lo.x(), b.lo.y(), b.lo.z()), py::make_tuple(b.hi.x(), b.hi.y(), b.hi.z()));
        }, "Its bounding box ((x, y, z) low, (x, y, z) high), m (a plane: the square it is drawn as).")
        .def_property_readonly("vertices", [](const Obstacle& o) { return vertices_array(o.built->tessellate()); },
                               "The triangle mesh it is drawn as: vertices (n, 3) float64, m.")
        .def_property_readonly("faces", [](const Obstacle& o) { return faces_array(o.built->tessellate()); },
                               "The triangle mesh it is drawn as: faces (m, 3) int32.")
        .def("distance", [](const Obstacle& o, py::array_t<double, py::array::c_style | py::array::forcecast> points) {
            if (points.ndim() != 2 || points.shape(1) != 3) throw py::value_error("distance(): expected points of shape (n, 3)");
            const auto p = points.unchecked<2>();
            py::array_t<double> d(points.shape(0));
            auto r = d.mutable_unchecked<1>();
            for (py::ssize_t k = 0; k < points.shape(0); ++k) r(k) = o.built->distance(Vec3(p(k, 0), p(k, 1), p(k, 2)));
            return d;
        }, py::arg("points"), "Signed distance (m) of each point (n, 3) to the solid: > 0 outside, < 0 inside.")
        .def("__repr__", [](const Obstacle& o) { return "<woven.Obstacle " + o.kind + ">"; });
}

}  // namespace woven::python
