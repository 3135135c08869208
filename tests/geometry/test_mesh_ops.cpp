// The cloth grid as a mesh and its vertex normals (geometry/mesh_ops.hpp).
#include <cmath>

#include <gtest/gtest.h>

#include "woven/common/error.hpp"
#include "woven/geometry/mesh_ops.hpp"

using namespace woven;

namespace {

/// nu x nv points of the plane z = 0.3 x + 0.2 y, spacing 0.1 m, index i + nu * j.
Positions tilted_grid(int nu, int nv)
{
    Positions x;
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) x.emplace_back(0.1 * i, 0.1 * j, 0.03 * i + 0.02 * j);
    return x;
}

}  // namespace

TEST(GridMesh, TwoCounterClockwiseTrianglesPerCell)
{
    const geometry::TriangleMesh m = geometry::grid_mesh(tilted_grid(4, 3), 4, 3);
    ASSERT_EQ(m.faces.size(), 2u * 3 * 2);
    EXPECT_EQ(m.faces[0], Eigen::Vector3i(0, 1, 5));
    EXPECT_EQ(m.faces[1], Eigen::Vector3i(0, 5, 4));
    EXPECT_EQ(m.faces.back(), Eigen::Vector3i(6, 11, 10));
    EXPECT_THROW(geometry::grid_mesh(tilted_grid(4, 3), 3, 3), InputError);
    EXPECT_THROW(geometry::grid_mesh(Positions(3), 3, 1), InputError);
}

TEST(VertexNormals, APlaneGivesItsNormalEverywhereAndALoneVertexUp)
{
    geometry::TriangleMesh m = geometry::grid_mesh(tilted_grid(5, 4), 5, 4);
    m.vertices.emplace_back(9, 9, 9);  // touched by no face
    const Positions n = geometry::vertex_normals(m);
    ASSERT_EQ(n.size(), 21u);
    const Vec3 plane = Vec3(-0.3, -0.2, 1).normalized();
    for (int k = 0; k < 20; ++k) EXPECT_LT((n[k] - plane).norm(), 1e-12) << k;
    EXPECT_EQ(n[20], Vec3(0, 0, 1));
}
