#ifndef SOFTBENCH_TESTS_SUPPORT_RENDERED_TRUTH_H_
#define SOFTBENCH_TESTS_SUPPORT_RENDERED_TRUTH_H_

#include <Eigen/Core>
#include <string>
#include <vector>

namespace softbench {

// The renderer's per-frame truth (`render --truth`, docs/rendering.md), read
// by its column names: each frame's time and every head's displacement and
// image position, and the camera's motion.
struct RenderedTruth {
  std::vector<double> time_s;
  // [frame][head]: the head's displacement (y, z) in the bench plane.
  std::vector<std::vector<Eigen::Vector2d>> displacement_mm;
  // [frame][head]: the head centre's position in the image.
  std::vector<std::vector<Eigen::Vector2d>> position_px;
  std::vector<Eigen::Vector2d> camera_shift_px;
  std::vector<double> camera_roll_rad;

  int NumHeads() const {
    return displacement_mm.empty()
               ? 0
               : static_cast<int>(displacement_mm[0].size());
  }
  // Each head's median displacement over the frames with start_s <= t <
  // end_s, as (y1, z1, y2, z2, ...); the same window median that
  // measurement reports.
  Eigen::VectorXd MedianDisplacementMm(double start_s, double end_s) const;
};

RenderedTruth ReadRenderedTruth(const std::string& path);

}  // namespace softbench

#endif  // SOFTBENCH_TESTS_SUPPORT_RENDERED_TRUTH_H_
