// Output writers: cloth OBJ/PLY and atomic writes.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>
#include <cstdio>

#include <unistd.h>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "woven/common/error.hpp"
#include "woven/geometry/mesh_ops.hpp"
#include "woven/io/output.hpp"
#include "woven/model/cloth_model.hpp"

namespace fs = std::filesystem;
using namespace woven;
using ::testing::HasSubstr;

namespace {

std::vector<std::string> lines_starting(const std::string& text, const std::string& prefix)
{
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);)
        if (line.rfind(prefix, 0) == 0) out.push_back(line);
    return out;
}

/// A 3 x 3 grid, flat at z = 0.5, spacing 0.1, slightly perturbed so normals are not trivial.
Positions grid3()
{
    Positions x = model::flat_grid(model::Grid{3, 3, 0.1}, Vec3(0, 0, 0.5));
    x[4].z() += 0.01;
    return x;
}

fs::path temp_dir(const std::string& name)
{
    const fs::path d = fs::temp_directory_path() / ("woven_test_output_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

}  // namespace

TEST(ClothObj, CountsAndIndicesOfA3x3Grid)
{
    const std::string obj = io::cloth_obj(grid3(), 3, 3);
    EXPECT_EQ(lines_starting(obj, "v ").size(), 9u);
    EXPECT_EQ(lines_starting(obj, "vt ").size(), 9u);
    EXPECT_EQ(lines_starting(obj, "vn ").size(), 9u);
    const auto faces = lines_starting(obj, "f ");
    ASSERT_EQ(faces.size(), 8u);  // 2 per cell, 4 cells
    for (const auto& f : faces) {
        std::istringstream in(f.substr(2));
        int corners = 0;
        for (std::string c; in >> c; ++corners) {
            int v = 0, t = 0, n = 0;
            ASSERT_EQ(std::sscanf(c.c_str(), "%d/%d/%d", &v, &t, &n), 3) << f;
            for (int k : {v, t, n}) {
                EXPECT_GE(k, 1) << f;
                EXPECT_LE(k, 9) << f;
            }
        }
        EXPECT_EQ(corners, 3) << f;
    }
    EXPECT_THAT(obj, HasSubstr("units: m"));
    EXPECT_THAT(obj, HasSubstr("grid 3 x 3"));
    // Texture coordinates: corner (i, j) = (2, 2) is the last vt, (1, 1).
    EXPECT_EQ(lines_starting(obj, "vt ").back(), "vt 1 1");
    EXPECT_EQ(lines_starting(obj, "vt ")[1], "vt 0.5 0");
}

TEST(ClothObj, FlatGridNormalsPointUp)
{
    const Positions x = model::flat_grid(model::Grid{4, 3, 0.1}, Vec3(0, 0, 1));
    const Positions n = geometry::vertex_normals(geometry::grid_mesh(x, 4, 3));
    ASSERT_EQ(n.size(), 12u);
    for (const auto& v : n) EXPECT_NEAR((v - Vec3::UnitZ()).norm(), 0.0, 1e-12);
    const std::string obj = io::cloth_obj(x, 4, 3);
    for (const auto& l : lines_starting(obj, "vn ")) EXPECT_EQ(l, "vn 0.000000 0.000000 1.000000");
}

TEST(ClothObj, RejectsMismatchedGrid)
{
    EXPECT_THROW(io::cloth_obj(grid3(), 4, 3), InputError);
    EXPECT_THROW(io::cloth_ply(grid3(), 3, 4), InputError);
}

TEST(ClothPly, HeaderCountsAndIndicesOfA3x3Grid)
{
    const std::string ply = io::cloth_ply(grid3(), 3, 3, {}, io::PlyFormat::ASCII);
    std::istringstream in(ply);
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "ply");
    std::getline(in, line);
    EXPECT_EQ(line, "format ascii 1.0");
    EXPECT_THAT(ply, HasSubstr("element vertex 9\n"));
    EXPECT_THAT(ply, HasSubstr("element face 8\n"));
    EXPECT_THAT(ply, HasSubstr("property float nx\n"));
    EXPECT_THAT(ply, HasSubstr("property float v\n"));
    while (std::getline(in, line) && line != "end_header") { }
    ASSERT_EQ(line, "end_header");
    for (int k = 0; k < 9; ++k) {
        ASSERT_TRUE(std::getline(in, line));
        std::istringstream vl(line);
        double vals[8];
        int count = 0;
        while (count < 8 && vl >> vals[count]) ++count;
        EXPECT_EQ(count, 8) << line;
        EXPECT_NEAR(Vec3(vals[3], vals[4], vals[5]).norm(), 1.0, 1e-5) << line;
    }
    int faces = 0;
    while (std::getline(in, line)) {
        if (line.empty()) continue;
        std::istringstream fl(line);
        int n = 0, a = -1, b = -1, c = -1;
        fl >> n >> a >> b >> c;
        EXPECT_EQ(n, 3);
        for (int k : {a, b, c}) {
            EXPECT_GE(k, 0);
            EXPECT_LT(k, 9);
        }
        ++faces;
    }
    EXPECT_EQ(faces, 8);
}

TEST(WriteFileAtomic, WritesAndReplacesWithoutLeavingTmp)
{
    const fs::path d = temp_dir("write");
    const std::string path = (d / "cloth.obj").string();
    io::write_file_atomic(path, "first\n");
    io::write_file_atomic(path, "second version\n");
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    EXPECT_EQ(s.str(), "second version\n");
    EXPECT_FALSE(fs::exists(path + ".tmp"));
    int entries = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(d)) ++entries;
    EXPECT_EQ(entries, 1);
    fs::remove_all(d);
}

TEST(WriteFileAtomic, MissingDirectoryThrowsRuntimeError)
{
    const fs::path d = temp_dir("missing");
    const std::string path = (d / "no" / "such" / "dir" / "out.ply").string();
    try {
        io::write_file_atomic(path, "data");
        FAIL() << "expected RuntimeError";
    } catch (const RuntimeError& e) {
        EXPECT_THAT(std::string(e.what()), HasSubstr("out.ply"));
    }
    EXPECT_FALSE(fs::exists(path));
    EXPECT_FALSE(fs::exists(path + ".tmp"));
    fs::remove_all(d);
}

TEST(WriteFileAtomic, TargetIsADirectoryLeavesNoTmp)
{
    const fs::path d = temp_dir("dir");
    fs::create_directories(d / "target");
    const std::string path = (d / "target").string();
    EXPECT_THROW(io::write_file_atomic(path, "data"), RuntimeError);
    EXPECT_FALSE(fs::exists(path + ".tmp"));
    EXPECT_TRUE(fs::is_directory(path));
    fs::remove_all(d);
}
