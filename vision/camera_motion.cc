#include "vision/camera_motion.h"

#include <Eigen/Geometry>
#include <cmath>

namespace softbench {

CameraMotion CameraMotion::FromImageShift(const CameraIntrinsics& intrinsics,
                                          const Eigen::Vector2d& shift_px,
                                          double roll_rad, double scale) {
  // A pan by a moves the optical axis's ray to x/z = tan(a); a tilt by b to
  // y/z = -tan(b). Small angles compose almost independently; ShiftPx gives
  // the exact shift of the result.
  CameraMotion motion;
  motion.rotation_rad =
      Eigen::Vector3d(-std::atan(shift_px.y() / intrinsics.fy_px),
                      std::atan(shift_px.x() / intrinsics.fx_px), roll_rad);
  motion.scale = scale;
  return motion;
}

Eigen::Matrix3d CameraMotion::CurrentFromReference() const {
  const double angle = rotation_rad.norm();
  const Eigen::Matrix3d rotation =
      angle > 0.0
          ? Eigen::AngleAxisd(angle, rotation_rad / angle).toRotationMatrix()
          : Eigen::Matrix3d::Identity();
  return Eigen::Vector3d(scale, scale, 1.0).asDiagonal() * rotation;
}

Eigen::Vector2d CameraMotion::ShiftPx(
    const CameraIntrinsics& intrinsics) const {
  const Eigen::Vector3d n = CurrentFromReference().col(2);
  return {intrinsics.fx_px * n.x() / n.z(), intrinsics.fy_px * n.y() / n.z()};
}

}  // namespace softbench
