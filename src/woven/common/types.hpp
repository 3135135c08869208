#pragma once
// Fixed-size Eigen aliases used across modules.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace woven {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Vec2 = Eigen::Vector2d;
template <int N> using VecN = Eigen::Matrix<double, N, 1>;
template <int N> using MatN = Eigen::Matrix<double, N, N>;
/// Particle positions, one 3-vector per particle (m).
using Positions = std::vector<Vec3, Eigen::aligned_allocator<Vec3>>;

}  // namespace woven
