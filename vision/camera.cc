#include "vision/camera.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <utility>
#include <vector>

namespace softbench {

CameraIntrinsics CameraIntrinsics::FromEquivalentFocalLength(
    double focal_35mm_mm, int width_px, int height_px) {
  // A 35-mm-equivalent focal length refers to the 43.27 mm diagonal of a
  // 36 x 24 mm frame.
  const double diagonal_35mm = std::hypot(36.0, 24.0);
  const double focal_px =
      focal_35mm_mm * std::hypot(width_px, height_px) / diagonal_35mm;
  CameraIntrinsics k;
  k.width_px = width_px;
  k.height_px = height_px;
  k.fx_px = k.fy_px = focal_px;
  k.cx_px = (width_px - 1) / 2.0;
  k.cy_px = (height_px - 1) / 2.0;
  return k;
}

cv::Matx33d CameraIntrinsics::CameraMatrix() const {
  return {fx_px, 0.0, cx_px, 0.0, fy_px, cy_px, 0.0, 0.0, 1.0};
}

std::optional<std::string> CameraIntrinsics::Problem() const {
  if (width_px < 16 || height_px < 16 || width_px > 16384 ||
      height_px > 16384) {
    return "resolution must be between 16 and 16384 pixels per side";
  }
  if (!(fx_px > 0.0) || !(fy_px > 0.0) || !std::isfinite(fx_px) ||
      !std::isfinite(fy_px)) {
    return "focal lengths must be finite and > 0 px";
  }
  if (!std::isfinite(cx_px) || !std::isfinite(cy_px)) {
    return "principal point must be finite";
  }
  for (double d : distortion) {
    if (!std::isfinite(d)) return "distortion coefficients must be finite";
  }
  const auto valid_std = [](double s) { return std::isfinite(s) && s >= 0.0; };
  if (!std::all_of(intrinsics_std_px.begin(), intrinsics_std_px.end(),
                   valid_std) ||
      !std::all_of(distortion_std.begin(), distortion_std.end(), valid_std)) {
    return "standard errors must be finite and >= 0";
  }
  return std::nullopt;
}

Camera::Camera(const CameraIntrinsics& intrinsics,
               Eigen::Matrix3d camera_from_world, Eigen::Vector3d translation)
    : intrinsics_(intrinsics),
      camera_from_world_(std::move(camera_from_world)),
      translation_(std::move(translation)) {}

Camera Camera::LookingDown(const CameraIntrinsics& intrinsics,
                           const Eigen::Vector3d& target, double distance_mm,
                           double tilt_x_rad, double tilt_y_rad) {
  // Untilted: camera x = world X, camera y = -world Y, camera z = -world Z.
  Eigen::Matrix3d untilted;
  untilted << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  const Eigen::Matrix3d tilt =
      (Eigen::AngleAxisd(tilt_x_rad, Eigen::Vector3d::UnitX()) *
       Eigen::AngleAxisd(tilt_y_rad, Eigen::Vector3d::UnitY()))
          .toRotationMatrix();
  const Eigen::Matrix3d camera_from_world = tilt * untilted;
  // The target lies on the optical axis at `distance_mm`.
  const Eigen::Vector3d translation =
      Eigen::Vector3d(0, 0, distance_mm) - camera_from_world * target;
  return {intrinsics, camera_from_world, translation};
}

bool Camera::HasDistortion() const {
  for (double d : intrinsics_.distortion) {
    if (d != 0.0) return true;
  }
  return false;
}

Eigen::Vector2d Camera::Distort(const Eigen::Vector2d& normalized) const {
  // OpenCV's model (calib3d documentation, "Detailed description").
  const auto& [k1, k2, p1, p2, k3] = intrinsics_.distortion;
  const double x = normalized.x(), y = normalized.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const double xd = x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x);
  const double yd = y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y;
  return {intrinsics_.fx_px * xd + intrinsics_.cx_px,
          intrinsics_.fy_px * yd + intrinsics_.cy_px};
}

Eigen::Vector2d Camera::Project(const Eigen::Vector3d& point_in_world) const {
  const Eigen::Vector3d p = camera_from_world_ * point_in_world + translation_;
  return Distort(p.head<2>() / p.z());
}

Eigen::Vector2d Camera::Undistort(const Eigen::Vector2d& pixel) const {
  if (!HasDistortion()) {
    return {(pixel.x() - intrinsics_.cx_px) / intrinsics_.fx_px,
            (pixel.y() - intrinsics_.cy_px) / intrinsics_.fy_px};
  }
  return UndistortPixels({{pixel.x(), pixel.y()}})[0];
}

std::vector<Eigen::Vector2d> Camera::UndistortPixels(
    const std::vector<cv::Point2d>& pixels) const {
  std::vector<cv::Point2d> out;
  cv::undistortPoints(
      pixels, out, intrinsics_.CameraMatrix(), intrinsics_.distortion,
      cv::noArray(), cv::noArray(),
      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100,
                       1e-15));
  std::vector<Eigen::Vector2d> normalized;
  normalized.reserve(out.size());
  for (const cv::Point2d& p : out) normalized.emplace_back(p.x, p.y);
  return normalized;
}

Eigen::Matrix3d Camera::NormalizedFromPlane(double plane_height_mm) const {
  // x_c = R (X, Y, h) + t = [r1 r2 (h r3 + t)] (X, Y, 1).
  Eigen::Matrix3d h;
  h.col(0) = camera_from_world_.col(0);
  h.col(1) = camera_from_world_.col(1);
  h.col(2) = plane_height_mm * camera_from_world_.col(2) + translation_;
  return h;
}

}  // namespace softbench
