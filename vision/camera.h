#ifndef SOFTBENCH_VISION_CAMERA_H_
#define SOFTBENCH_VISION_CAMERA_H_

#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

namespace softbench {

// Pinhole intrinsics with OpenCV's distortion model and coefficient order
// (k1, k2, p1, p2, k3). Pixel centres are at integer coordinates, as in
// OpenCV.
struct CameraIntrinsics {
  int width_px = 1920;
  int height_px = 1080;
  double fx_px = 2647.0;
  double fy_px = 2647.0;
  double cx_px = 959.5;
  double cy_px = 539.5;
  std::array<double, 5> distortion{};  // k1, k2, p1, p2, k3
  // Standard errors of fx, fy, cx, cy [px] and of the distortion
  // coefficients, as a calibration's fit gives them (calibrate-camera
  // writes them): what the uncertainty budget propagates. 0: exact or not
  // known.
  std::array<double, 4> intrinsics_std_px{};
  std::array<double, 5> distortion_std{};

  // The thesis's set-up (fig. 4.7): a 52 mm 35-mm-equivalent focal length,
  // centred principal point, no distortion, at the given resolution.
  static CameraIntrinsics FromEquivalentFocalLength(double focal_35mm_mm,
                                                    int width_px,
                                                    int height_px);

  cv::Matx33d CameraMatrix() const;
  std::optional<std::string> Problem() const;
};

// A camera above the mechanism. World frame (mm): X = the mechanism's y, Y =
// the mechanism's z, Z = height above the tag plane, toward the camera. Pose:
// x_camera = camera_from_world * X_world + translation (OpenCV's camera frame:
// x right, y down, z forward).
class Camera {
 public:
  Camera(const CameraIntrinsics& intrinsics, Eigen::Matrix3d camera_from_world,
         Eigen::Vector3d translation);

  // A camera `distance_mm` from `target` (world), looking at it from above
  // with image right along +X and image up along +Y when untilted, then tilted
  // about the image's x axis by `tilt_x_rad` and its y axis by `tilt_y_rad`
  // around the target (the target stays at the image centre).
  static Camera LookingDown(const CameraIntrinsics& intrinsics,
                            const Eigen::Vector3d& target, double distance_mm,
                            double tilt_x_rad, double tilt_y_rad);

  const CameraIntrinsics& intrinsics() const { return intrinsics_; }
  const Eigen::Matrix3d& camera_from_world() const {
    return camera_from_world_;
  }
  const Eigen::Vector3d& translation() const { return translation_; }

  // World point to distorted pixel coordinates.
  Eigen::Vector2d Project(const Eigen::Vector3d& point_in_world) const;
  // Ideal normalised image coordinates (x/z, y/z) to distorted pixels.
  Eigen::Vector2d Distort(const Eigen::Vector2d& normalized) const;
  // Distorted pixels to ideal normalised coordinates (OpenCV's iterative
  // undistortion, run to convergence rather than its default 5 iterations).
  Eigen::Vector2d Undistort(const Eigen::Vector2d& pixel) const;
  // The same for many pixels in one call (OpenCV's batch undistortion).
  std::vector<Eigen::Vector2d> UndistortPixels(
      const std::vector<cv::Point2d>& pixels) const;
  bool HasDistortion() const;

  // Homography from a world plane Z = height (homogeneous (X, Y, 1)) to
  // ideal normalised image coordinates.
  Eigen::Matrix3d NormalizedFromPlane(double plane_height_mm) const;

 private:
  CameraIntrinsics intrinsics_;
  Eigen::Matrix3d camera_from_world_;
  Eigen::Vector3d translation_;
};

}  // namespace softbench

#endif  // SOFTBENCH_VISION_CAMERA_H_
