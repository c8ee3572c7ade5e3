#ifndef SOFTBENCH_PIPELINES_REPORTS_TUNE_PAGE_H_
#define SOFTBENCH_PIPELINES_REPORTS_TUNE_PAGE_H_

#include <array>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "vision/color_segmentation.h"

namespace softbench {

// One colour as `tune` found it, the page's starting point.
struct TunedColor {
  std::string name;             // a DotColors() name
  std::array<int, 6> bounds{};  // h_lo h_hi s_lo s_hi v_lo v_hi to start from
  bool found = false;           // dot-sized blobs in its range
  std::string why_not;          // when not found: it is reported absent
  double dot_radius_px = 0.0;   // the dots' radius (when found)
  int dots = 0;                 // dots `tune` accepted
};

// The Color Thresholder replacement: a self-contained page (no library, no
// network) with the picture, HSV range sliders per colour, the live mask and
// the dot-sized blobs drawn over the picture, and the bounds as the YAML to
// paste into the plan's markers. The page's blob test is the area window of
// `segmentation` (validate also opens and closes the mask and tests the
// shape). A URL fragment such as #red=0,10,100,255,50,255 moves a colour's
// sliders, as a person would, so a link can share a setting.
std::string TunePageHtml(const cv::Mat& bgr, const std::string& source,
                         double time_s, const std::vector<TunedColor>& colors,
                         const SegmentationOptions& segmentation);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_REPORTS_TUNE_PAGE_H_
