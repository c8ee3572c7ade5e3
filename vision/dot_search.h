#ifndef SOFTBENCH_VISION_DOT_SEARCH_H_
#define SOFTBENCH_VISION_DOT_SEARCH_H_

#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "vision/color_segmentation.h"
#include "vision/frame_source.h"

namespace softbench {

struct DotSearchOptions {
  // The coarse pass reduces the region by the largest whole factor that
  // keeps a dot's radius at least this many pixels (the thesis's 4 mm dots,
  // 11 px at 1080p: factor 3), at most max_reduction. Below a factor of 2
  // the search is one pass at full resolution.
  double min_coarse_radius_px = 3.5;
  int max_reduction = 4;

  std::optional<std::string> Problem() const;
};

// The reduction SearchDots uses for dots of `dot_radius_px`.
int DotSearchReduction(double dot_radius_px, const DotSearchOptions& options);

// The blobs of `range` in `region` of the frame, as SegmentDots finds them
// in the full-resolution region, at a fraction of the cost. A coarse pass
// segments the region reduced by averaging (1/f^2 of the pixels; 4:2:0
// video carries its colour at half resolution anyway) and drops components
// far too small or too large to be a dot (counted as rejected by size).
// Each remaining candidate is segmented again at full resolution in a box
// around it, grown by a dot radius (beyond the reach of the mask cleaning),
// so accepted blobs carry full-resolution centroids, areas and shapes. A
// blob that runs out of its box belongs to something larger than a dot and
// counts as rejected by shape.
BlobSummary SearchDots(const FrameSource& frame, const cv::Rect& region,
                       const HsvRange& range,
                       const SegmentationOptions& segmentation,
                       const DotSearchOptions& options = {});

}  // namespace softbench

#endif  // SOFTBENCH_VISION_DOT_SEARCH_H_
