#ifndef SOFTBENCH_VISION_PLANE_MAPPING_H_
#define SOFTBENCH_VISION_PLANE_MAPPING_H_

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "vision/camera.h"

namespace softbench {

// Where the camera's centre is seen from the mapped plane: its foot (the
// plane point straight below it) [mm, plane coordinates] and its height
// above the plane [mm]. A point raised by h above the plane at p appears,
// through the plane's mapping, at foot + (p - foot) H / (H - h): the
// parallax a lifted head shows (issue 27).
struct CameraAbovePlane {
  Eigen::Vector2d foot_mm = Eigen::Vector2d::Zero();
  double height_mm = 0.0;
  // Whether there is one: a mapping from a tag seen below its dot plane
  // has none, and lifts cannot be measured through it.
  bool Found() const { return height_mm > 0.0 && std::isfinite(height_mm); }
};

// Image pixels to millimetres on the plane the dots move in, in the
// mechanism's world axes (y, z). Lens distortion, when the intrinsics carry
// it, is removed from the points (never by warping frames), then a
// homography takes ideal image coordinates to the plane; so a tilted camera's
// perspective is corrected exactly for points on that plane.
class PlaneMapping {
 public:
  // From an AprilTag: its four outer corners (OpenCV pixels, libapriltag's
  // order: counter-clockwise in the printed tag from bottom-left), its side
  // [mm], and the height of the dot plane above the tag plane [mm]. The tag's
  // printed +x is world +y and its printed up world +z; the origin is the
  // tag's centre. The camera's pose comes from the corners (planar PnP), so
  // the dot plane's homography follows from the tag plane's.
  static PlaneMapping FromTag(const CameraIntrinsics& intrinsics,
                              const std::array<Eigen::Vector2d, 4>& corners,
                              double tag_size_mm, double plane_height_mm);

  // Without a tag (thesis 4.1.3's pixel-to-mm factor): a fronto-parallel
  // camera with `mm_per_px` at the image centre and world +y along image
  // right turned counter-clockwise on screen by `image_rotation_rad`.
  static PlaneMapping FromScale(const CameraIntrinsics& intrinsics,
                                double mm_per_px, double image_rotation_rad);

  // The same plane seen after the camera moved: `current_from_reference`
  // takes this mapping's ideal normalised coordinates to the moved camera's
  // (CameraMotion::CurrentFromReference), so a frame registered to the
  // bench maps its pixels to the same millimetres.
  PlaneMapping AfterCameraMotion(
      const Eigen::Matrix3d& current_from_reference) const;

  Eigen::Vector2d ToPlane(const Eigen::Vector2d& pixel) const;
  std::vector<Eigen::Vector2d> ToPlane(
      const std::vector<Eigen::Vector2d>& pixels) const;
  // Millimetres per pixel at a pixel (the mean of the two axes' local
  // scales), for sizing dots and search regions.
  double MmPerPixelAt(const Eigen::Vector2d& pixel) const;
  // The plane point's pixel (inverse of ToPlane).
  Eigen::Vector2d ToPixel(const Eigen::Vector2d& plane_mm) const;
  // Angle between the camera's optical axis and the plane's normal [rad]:
  // the tilt the tag's pose corrects (0 for a mapping from a scale).
  double TiltRad() const;
  // The camera's height above the tag's plane [mm], from the tag's pose
  // (0 for a mapping from a scale): a dot plane must lie below it.
  double CameraHeightMm() const;
  // The camera's centre against the mapped plane, from the homography: a
  // tag's pose, or for a mapping from a scale a fronto-parallel camera at
  // fx mm_per_px (as right as the intrinsics' focal length).
  CameraAbovePlane CameraAbove() const;

  const CameraIntrinsics& intrinsics() const { return camera_.intrinsics(); }

 private:
  PlaneMapping(Camera camera, const Eigen::Matrix3d& plane_from_normalized);

  Camera camera_;  // its intrinsics (undistortion) and the tag's pose
  Eigen::Matrix3d plane_from_normalized_;
  Eigen::Matrix3d normalized_from_plane_;  // its inverse, for ToPixel
};

}  // namespace softbench

#endif  // SOFTBENCH_VISION_PLANE_MAPPING_H_
