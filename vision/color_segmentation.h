#ifndef SOFTBENCH_VISION_COLOR_SEGMENTATION_H_
#define SOFTBENCH_VISION_COLOR_SEGMENTATION_H_

#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

namespace softbench {

// An HSV box in OpenCV's 8-bit units (hue 0..179, saturation and value
// 0..255). Red straddles hue 0: a range with hue_low > hue_high wraps through
// 180, e.g. [170, 10] is 170..179 together with 0..10 (one range, not two).
struct HsvRange {
  int hue_low = 0, hue_high = 179;
  int saturation_low = 0, saturation_high = 255;
  int value_low = 0, value_high = 255;

  // From [h_low, h_high, s_low, s_high, v_low, v_high], the order plans
  // and `softbench tune` use.
  static HsvRange FromBounds(const std::array<int, 6>& bounds);

  bool Wraps() const { return hue_low > hue_high; }
  bool Contains(const cv::Vec3b& hsv) const;
};

struct SegmentationOptions {
  // Expected dot radius [px]; sets the structuring element and the area
  // window. Must be set (> 0) by the caller.
  double dot_radius_px = 0.0;
  // Disk radius of the opening (removes specks) and closing (fills holes)
  // as a fraction of the dot radius, at least 1 px (thesis 4.1.3 used imopen
  // with a disk). 0.15 removes specks up to 30 % of the dot's diameter:
  // 4:2:0 chroma noise comes in 2 x 2 px blocks; a larger disk costs time
  // with the square of its radius.
  double morphology_fraction = 0.15;
  // Accepted area as a fraction of pi r^2 (motion blur and the 4:2:0 chroma
  // blur change it; a tube or a table stain far exceeds it).
  double min_area_fraction = 0.35;
  double max_area_fraction = 2.5;
  // area^2 / (2 pi polar moment): 1 for a disk, ~0.7 for a 2:1 ellipse,
  // 0.25 for a 7:1 bar (a moment measure: no contour tracing, and steady
  // on pixel grids, where a traced perimeter overestimates by ~8 %).
  double min_circularity = 0.6;
  // Area over bounding-box area; a disk is pi/4 = 0.785.
  double min_fill = 0.55;

  std::optional<std::string> Problem() const;
};

// One connected component of a colour mask.
struct Blob {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();  // binary, pixels
  double area_px = 0.0;
  double circularity = 0.0;
  double fill = 0.0;
  cv::Rect box;
};

struct BlobSummary {
  std::vector<Blob> accepted;
  int rejected_area = 0;   // too small or too large
  int rejected_shape = 0;  // not round or not filled enough
  int TotalRejected() const { return rejected_area + rejected_shape; }
};

// Pixels of `bgr` (CV_8UC3) inside `range`, as a 0/255 mask.
cv::Mat ColorMask(const cv::Mat& bgr, const HsvRange& range);

// Opening then closing with an elliptical (disk) element sized by the dot
// radius, as the thesis's imopen plus the hole filling it lacked.
void CleanMask(const SegmentationOptions& options, cv::Mat* mask);

// Connected components of a cleaned mask, filtered by area, circularity and
// fill; `offset` is added to centroids and boxes (for masks of a region).
BlobSummary FindBlobs(const cv::Mat& mask, const SegmentationOptions& options,
                      const cv::Point& offset = {0, 0});

// A dot radius [px] for a raw colour mask when the scale is not known yet:
// the median equivalent radius (sqrt(area / pi)) of its components of at
// least 12 px; 0 when there are none.
double EstimateDotRadius(const cv::Mat& mask);

// The whole of a cleaned mask as one blob, when it is one: its pixels pass
// the area and shape filters (moments about their common centroid, so two
// separate blobs fail as one elongated shape) and stay clear of the mask's
// border; nullopt otherwise. FindBlobs' answer for a region that holds only
// the tracked dot, without labelling components.
std::optional<Blob> SingleBlob(const cv::Mat& mask,
                               const SegmentationOptions& options,
                               const cv::Point& offset = {0, 0});

// ColorMask, CleanMask and FindBlobs in one call.
BlobSummary SegmentDots(const cv::Mat& bgr, const HsvRange& range,
                        const SegmentationOptions& options,
                        const cv::Point& offset = {0, 0});

// What LearnHsvRange found: the suggested range and how it separates the
// dots from the rest of the image.
// The saturation-weighted circular mean hue (OpenCV units, 0-180) of the
// pixels of `hsv` (CV_8UC3, OpenCV's HSV) under `mask` within `box`: grey
// pixels, whose hue is noise, barely count, and red's hues on both sides of
// 0 average to red. NaN when no pixel is under the mask.
double MeanHue(const cv::Mat& hsv, const cv::Mat& mask, const cv::Rect& box);

struct LearnedHsvRange {
  HsvRange range;
  int dot_pixels = 0;         // pixels the range was learned from
  double dot_coverage = 0.0;  // fraction of them inside the range
  int outside_pixels = 0;     // pixels off the dots inside the range
};

// Learns an HSV range from the pixels of `bgr` under `dot_cores` (their
// saturated pixels are the cluster; `dot_regions` covers the whole dots,
// rims included, to count what else the range takes in): hue from the circular
// mean and the 1st..99th percentile spread, saturation and value from their
// 1st percentile, each widened by a margin so the next frame's noise and
// lighting still fall inside. Wraps through 180 for red.
LearnedHsvRange LearnHsvRange(const cv::Mat& bgr, const cv::Mat& dot_cores,
                              const cv::Mat& dot_regions);

}  // namespace softbench

#endif  // SOFTBENCH_VISION_COLOR_SEGMENTATION_H_
