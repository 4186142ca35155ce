#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace facesr {

using Vec3 = Eigen::Vector3d;
using Vec4 = Eigen::Vector4d;
using Mat3 = Eigen::Matrix3d;
using Vec3f = Eigen::Vector3f;
using Vec3i = Eigen::Vector3i;
using Vec4i = Eigen::Vector4i;
// Row-major N×3 / N×4 arrays: one row per vertex, triangle or tetrahedron.
using Points = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using Tris = Eigen::Matrix<int32_t, Eigen::Dynamic, 3, Eigen::RowMajor>;
using Tets = Eigen::Matrix<int32_t, Eigen::Dynamic, 4, Eigen::RowMajor>;

}  // namespace facesr
