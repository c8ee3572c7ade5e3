#ifndef SOFTBENCH_TESTS_VISION_BOARD_IMAGES_H_
#define SOFTBENCH_TESTS_VISION_BOARD_IMAGES_H_

#include <opencv2/core.hpp>
#include <vector>

#include "vision/camera.h"

namespace softbench {

// Renders a checkerboard with `corners_x` x `corners_y` inner corners and a
// white margin of one square, centred on the world origin in the plane
// Z = 0, as cameras with one set of intrinsics see it (distortion included):
// 8-bit grey images whose edges are box-filtered over each pixel's footprint
// on the board, with Gaussian noise (seeded).
class BoardRenderer {
 public:
  BoardRenderer(const CameraIntrinsics& intrinsics, int corners_x,
                int corners_y, double square_mm);
  cv::Mat Render(const Camera& camera, double noise_dn, int seed) const;

 private:
  CameraIntrinsics intrinsics_;
  int corners_x_, corners_y_;
  double square_mm_;
  std::vector<Eigen::Vector2d> normalized_;  // of every pixel centre
};

// Views of such a board filling the field at several tilts, for calibration.
std::vector<Camera> BoardViews(const CameraIntrinsics& intrinsics,
                               double distance_mm);

}  // namespace softbench

#endif  // SOFTBENCH_TESTS_VISION_BOARD_IMAGES_H_
