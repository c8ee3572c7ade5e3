#ifndef SOFTBENCH_TESTS_SUPPORT_DRAWN_TAG_H_
#define SOFTBENCH_TESTS_SUPPORT_DRAWN_TAG_H_

#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>

#include "pipelines/formats/test_plan.h"
#include "vision/tag_bitmap.h"

namespace softbench {

// A tag drawn cell by cell, pixel-sharp, in a grey 8-bit frame.
struct DrawnTag {
  cv::Mat luma;  // CV_8UC1: table 120, ink 30, paper 220
  // The black border's outer corners, as TagDetection::corners.
  std::array<Eigen::Vector2d, 4> corners;
};

// `bitmap` with cells of `cell_px` pixels, its quiet zone's top-left
// corner at pixel `origin`, in a frame of `frame`.
DrawnTag DrawTag(const TagBitmap& bitmap, int cell_px, cv::Size frame,
                 cv::Point origin);

// A delta plan of one test point whose tag is tag36h11 id 7, 25 mm across
// (DrawTag's and the renderer's tag in the tag's own tests).
TestPlan TagSevenPlan();

}  // namespace softbench

#endif  // SOFTBENCH_TESTS_SUPPORT_DRAWN_TAG_H_
