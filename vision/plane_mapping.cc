#include "vision/plane_mapping.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <utility>

namespace softbench {

PlaneMapping::PlaneMapping(Camera camera,
                           const Eigen::Matrix3d& plane_from_normalized)
    : camera_(std::move(camera)),
      plane_from_normalized_(plane_from_normalized),
      normalized_from_plane_(plane_from_normalized.inverse()) {}

PlaneMapping PlaneMapping::FromTag(
    const CameraIntrinsics& intrinsics,
    const std::array<Eigen::Vector2d, 4>& corners, double tag_size_mm,
    double plane_height_mm) {
  const double h = tag_size_mm / 2.0;
  // libapriltag's order in the printed tag (x right, y up): bottom-left,
  // bottom-right, top-right, top-left; world X = +y, Y = +z, Z up.
  const std::vector<cv::Point3d> object = {
      {-h, -h, 0}, {h, -h, 0}, {h, h, 0}, {-h, h, 0}};
  std::vector<cv::Point2d> image;
  for (const Eigen::Vector2d& c : corners) image.emplace_back(c.x(), c.y());
  cv::Vec3d rvec, tvec;
  cv::solvePnP(object, image, intrinsics.CameraMatrix(), intrinsics.distortion,
               rvec, tvec, false, cv::SOLVEPNP_IPPE);
  cv::Matx33d r;
  cv::Rodrigues(rvec, r);
  Eigen::Matrix3d camera_from_world;
  cv::cv2eigen(r, camera_from_world);
  const Camera camera(intrinsics, camera_from_world,
                      Eigen::Vector3d(tvec[0], tvec[1], tvec[2]));
  return {camera, camera.NormalizedFromPlane(plane_height_mm).inverse()};
}

PlaneMapping PlaneMapping::FromScale(const CameraIntrinsics& intrinsics,
                                     double mm_per_px,
                                     double image_rotation_rad) {
  // Normalised (x right, y down) to pixels from the centre with y up, then
  // turned by the rotation and scaled.
  const double c = std::cos(image_rotation_rad),
               s = std::sin(image_rotation_rad);
  Eigen::Matrix3d m = Eigen::Matrix3d::Identity();
  Eigen::Matrix2d rotation;
  rotation << c, s, -s, c;  // world axes are the image's turned by +angle
  m.topLeftCorner<2, 2>() =
      mm_per_px * rotation *
      Eigen::Vector2d(intrinsics.fx_px, -intrinsics.fy_px).asDiagonal();
  const Camera camera(intrinsics, Eigen::Matrix3d::Identity(),
                      Eigen::Vector3d::Zero());
  return {camera, m};
}

PlaneMapping PlaneMapping::AfterCameraMotion(
    const Eigen::Matrix3d& current_from_reference) const {
  return {camera_, plane_from_normalized_ * current_from_reference.inverse()};
}

Eigen::Vector2d PlaneMapping::ToPlane(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector3d q =
      plane_from_normalized_ * camera_.Undistort(pixel).homogeneous();
  return q.head<2>() / q.z();
}

std::vector<Eigen::Vector2d> PlaneMapping::ToPlane(
    const std::vector<Eigen::Vector2d>& pixels) const {
  std::vector<Eigen::Vector2d> out;
  out.reserve(pixels.size());
  if (!camera_.HasDistortion()) {
    for (const Eigen::Vector2d& p : pixels) out.push_back(ToPlane(p));
    return out;
  }
  std::vector<cv::Point2d> cv_pixels;
  for (const Eigen::Vector2d& p : pixels) cv_pixels.emplace_back(p.x(), p.y());
  for (const Eigen::Vector2d& n : camera_.UndistortPixels(cv_pixels)) {
    const Eigen::Vector3d q = plane_from_normalized_ * n.homogeneous();
    out.emplace_back(q.head<2>() / q.z());
  }
  return out;
}

double PlaneMapping::MmPerPixelAt(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector2d p = ToPlane(pixel);
  const double dx = (ToPlane(pixel + Eigen::Vector2d(1, 0)) - p).norm();
  const double dy = (ToPlane(pixel + Eigen::Vector2d(0, 1)) - p).norm();
  return 0.5 * (dx + dy);
}

Eigen::Vector2d PlaneMapping::ToPixel(const Eigen::Vector2d& plane_mm) const {
  const Eigen::Vector3d n = normalized_from_plane_ * plane_mm.homogeneous();
  return camera_.Distort(n.head<2>() / n.z());
}

double PlaneMapping::CameraHeightMm() const {
  // The camera centre in the tag's frame is -R^T t; the tag's plane is Z = 0
  // with Z toward the camera.
  return -(camera_.camera_from_world().transpose() * camera_.translation()).z();
}

CameraAbovePlane PlaneMapping::CameraAbove() const {
  // normalized_from_plane = s [r1 r2 t'] for the plane's axes r1, r2 in the
  // camera's frame and its origin t'; the centre is -R^T t' in the plane's
  // frame. The scale's sign cancels in r_i . t', and the height's sign is
  // that of the normal's choice, so it is taken positive.
  const double s = 0.5 * (normalized_from_plane_.col(0).norm() +
                          normalized_from_plane_.col(1).norm());
  const Eigen::Vector3d r1 = normalized_from_plane_.col(0) / s;
  const Eigen::Vector3d r2 = normalized_from_plane_.col(1) / s;
  const Eigen::Vector3d t = normalized_from_plane_.col(2) / s;
  CameraAbovePlane above;
  above.foot_mm = Eigen::Vector2d(-r1.dot(t), -r2.dot(t));
  above.height_mm = std::abs(r1.cross(r2).dot(t));
  return above;
}

double PlaneMapping::TiltRad() const {
  // normalized_from_plane is [r1 r2 t] up to scale: the plane's axes in the
  // camera frame; their cross product is its normal.
  const Eigen::Vector3d normal =
      normalized_from_plane_.col(0).normalized().cross(
          normalized_from_plane_.col(1).normalized());
  return std::acos(std::min(1.0, std::abs(normal.normalized().z())));
}

}  // namespace softbench
