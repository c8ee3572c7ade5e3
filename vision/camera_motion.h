#ifndef SOFTBENCH_VISION_CAMERA_MOTION_H_
#define SOFTBENCH_VISION_CAMERA_MOTION_H_

#include <Eigen/Core>

#include "vision/camera.h"

namespace softbench {

// How the camera moved since the reference frames. A phone on a tripod
// trembles, creeps and is bumped about its ball head, so its motion is a
// rotation about (nearly) its own centre, plus a change of image scale
// (focus breathing, a slide along the optical axis). Such motion acts on the
// ideal image as one homography, the same for every plane in view:
//   n_current ~ diag(scale, scale, 1) * R(rotation) * n_reference,
// with n = (x/z, y/z, 1) in OpenCV's camera frame (x right, y down, z
// forward). That is why the tag's plane registers the dots' plane.
struct CameraMotion {
  // Axis-angle rotation of the scene's rays, camera frame [rad]: about x
  // (tilt, moves the image vertically), y (pan, horizontally), z (roll).
  Eigen::Vector3d rotation_rad = Eigen::Vector3d::Zero();
  double scale = 1.0;

  // The motion that moves the content at the principal point by `shift_px`
  // and turns the image by `roll_rad` (clockwise on screen, as y points
  // down), scaled by `scale` about the principal point.
  static CameraMotion FromImageShift(const CameraIntrinsics& intrinsics,
                                     const Eigen::Vector2d& shift_px,
                                     double roll_rad, double scale = 1.0);

  // The homography on normalised homogeneous coordinates, reference frame
  // to current frame.
  Eigen::Matrix3d CurrentFromReference() const;
  // Where the content at the principal point moved [px] (exact).
  Eigen::Vector2d ShiftPx(const CameraIntrinsics& intrinsics) const;
  double roll_rad() const { return rotation_rad.z(); }
};

}  // namespace softbench

#endif  // SOFTBENCH_VISION_CAMERA_MOTION_H_
