// Eigen aliases used across libdem. All quantities are SI doubles: shear tests accumulate tiny
// increments over millions of steps, so single precision would drift.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace dem {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

inline constexpr double pi = 3.14159265358979323846;

}  // namespace dem
