#ifndef SOFTBENCH_VISION_COLOR_TUNING_H_
#define SOFTBENCH_VISION_COLOR_TUNING_H_

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "vision/color_segmentation.h"

namespace softbench {

struct ColorTuningOptions {
  // Expected dot radius [px]; 0: estimated from the mask's blobs.
  double dot_radius_px = 0.0;
  // Dot-sized blobs whose hue is further than this (OpenCV hue units, 2
  // degrees each) from the dots nearest the range's centre are another
  // colour in the same range (an orange part under a red range): they are
  // left out of the dots and of the suggested range. Printed dots of one
  // ink vary by 1-2 units across a frame.
  double max_hue_difference = 4.0;

  std::optional<std::string> Problem() const;
};

// One frame's colour segmentation made visible, and HSV bounds learned from
// its dots (what MATLAB's Color Thresholder app gave the thesis, 4.1.3).
struct ColorTuning {
  bool found = false;                // false: no dot-sized blobs in the range
  std::string why_not;               // when not found
  SegmentationOptions segmentation;  // with the radius used
  cv::Mat mask;                      // CV_8UC1, cleaned
  cv::Mat overlay;                   // the frame, blobs outlined and numbered
  BlobSummary blobs;
  // Dot-sized blobs of another hue in the range (max_hue_difference), and
  // their hues (OpenCV units).
  std::vector<Blob> other_hue;
  std::vector<double> other_hues;
  // Learned from the dots' cores (eroded away from the chroma-blurred rim);
  // dot_pixels == 0 when there were none.
  LearnedHsvRange learned;
};

ColorTuning TuneColor(const cv::Mat& bgr, const HsvRange& range,
                      const ColorTuningOptions& options);

}  // namespace softbench

#endif  // SOFTBENCH_VISION_COLOR_TUNING_H_
