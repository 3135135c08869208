// The OBJ reader (issue 13 defect 4): every number is checked, errors name the file and line.
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "woven/common/error.hpp"
#include "woven/io/mesh_file.hpp"

using namespace woven;

namespace {

const std::string kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

std::string obj_error(const std::string& text)
{
    try {
        io::parse_obj_mesh(text, "m.obj");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(ObjReader, ReadsVerticesAndFanTriangulatesPolygons)
{
    const auto m = io::parse_obj_mesh("# a quad\nv 0 0 0\nv 1 0 0 1.0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
                                      "o quad\ng g\ns off\nf 1/1/1 2//1 3/1 -1\n",
                                      "m.obj");
    ASSERT_EQ(m.vertices.size(), 4u);
    EXPECT_EQ(m.vertices[1], Vec3(1, 0, 0));
    ASSERT_EQ(m.faces.size(), 2u);
    EXPECT_EQ(m.faces[0], Eigen::Vector3i(0, 1, 2));
    EXPECT_EQ(m.faces[1], Eigen::Vector3i(0, 2, 3));
}

TEST(ObjReader, BadNumbersAreErrorsWithTheLine)
{
    // nan, inf and zz used to read as 0; 4294967299 wrapped to 3; 1e300 was "not finite".
    EXPECT_EQ(obj_error("v nan 0 0\n" + kTriangle + "f 1 2 3\n"),
              "m.obj:1: v: expected a number in [-1000000, 1000000], got 'nan'");
    EXPECT_EQ(obj_error(kTriangle + "v inf 0 0\nf 1 2 3\n"),
              "m.obj:4: v: expected a number in [-1000000, 1000000], got 'inf'");
    EXPECT_EQ(obj_error("v 0 zz 0\n"), "m.obj:1: v: expected a number in [-1000000, 1000000], got 'zz'");
    EXPECT_EQ(obj_error("v 0 0 1e300\n"), "m.obj:1: v: expected a number in [-1000000, 1000000], got '1e300'");
    EXPECT_EQ(obj_error("v 0 0\n"), "m.obj:1: v: expected 3 coordinates, got 2");
    EXPECT_EQ(obj_error(kTriangle + "f 1 2 4294967299\n"),
              "m.obj:4: f: expected a vertex index in [1, 10000000] or in [-3, -1] (relative), got '4294967299'");
    EXPECT_EQ(obj_error(kTriangle + "f 1 2 4\n"), "m.obj:4: f: vertex index 4 out of range (the file has 3 vertices)");
    EXPECT_EQ(obj_error(kTriangle + "f 1 2 0\n"),
              "m.obj:4: f: expected a vertex index in [1, 10000000] or in [-3, -1] (relative), got '0'");
    EXPECT_EQ(obj_error(kTriangle + "f 1 2 -4\n"),
              "m.obj:4: f: expected a vertex index in [1, 10000000] or in [-3, -1] (relative), got '-4'");
    EXPECT_EQ(obj_error(kTriangle + "f 1 2\n"), "m.obj:4: f: expected at least 3 vertices, got 2");
    EXPECT_EQ(obj_error(kTriangle + "f 1 x 3\n"),
              "m.obj:4: f: expected a vertex index in [1, 10000000] or in [-3, -1] (relative), got 'x'");
    EXPECT_EQ(obj_error(kTriangle), "m.obj: faces: the OBJ file has no faces");
    EXPECT_EQ(obj_error(kTriangle + "f 1 1 2\n"), "m.obj: faces: the OBJ file has no faces");  // degenerate only
}

TEST(ObjReader, MissingFileAndDirectory)
{
    EXPECT_THROW(io::load_obj_mesh("/nonexistent/x.obj"), InputError);
    EXPECT_THROW(io::load_obj_mesh("/tmp"), InputError);
}
