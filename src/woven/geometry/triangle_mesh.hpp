#pragma once
// An indexed triangle mesh (m): obstacles from OBJ files, tessellated primitives for rendering.
#include <vector>

#include <Eigen/Core>

#include "woven/common/types.hpp"

namespace woven::geometry {

struct TriangleMesh {
    std::vector<Vec3, Eigen::aligned_allocator<Vec3>> vertices;  ///< m
    std::vector<Eigen::Vector3i> faces;                           ///< counter-clockwise seen from outside
};

}  // namespace woven::geometry
