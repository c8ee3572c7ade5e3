#include "vision/color_tuning.h"

#include <fmt/format.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "util/check.h"

namespace softbench {
namespace {

cv::Point Pixel(const Eigen::Vector2d& p) {
  return {static_cast<int>(std::lround(p.x())),
          static_cast<int>(std::lround(p.y()))};
}

// The dots' cores, where the colour is the dot's own, and the regions around
// the dots, outside which any pixel in range is a false positive.
LearnedHsvRange LearnFromDots(const cv::Mat& bgr, const cv::Mat& mask,
                              const BlobSummary& blobs, double radius) {
  cv::Mat cores = cv::Mat::zeros(mask.size(), CV_8UC1);
  cv::Mat regions = cores.clone();
  for (const Blob& blob : blobs.accepted) {
    cv::circle(cores, Pixel(blob.centroid),
               std::max(1, static_cast<int>(0.7 * radius)), 255, cv::FILLED);
    cv::circle(regions, Pixel(blob.centroid),
               static_cast<int>(std::ceil(radius + 3)), 255, cv::FILLED);
  }
  cores &= mask;
  return LearnHsvRange(bgr, cores, regions);
}

cv::Mat Overlay(const cv::Mat& bgr, const cv::Mat& mask,
                const BlobSummary& blobs, double radius) {
  cv::Mat overlay = bgr.clone();
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  cv::drawContours(overlay, contours, -1, cv::Scalar(255, 255, 0), 1);
  for (size_t i = 0; i < blobs.accepted.size(); ++i) {
    const cv::Point c = Pixel(blobs.accepted[i].centroid);
    cv::circle(overlay, c, static_cast<int>(std::lround(radius + 4)),
               cv::Scalar(0, 255, 0), 2);
    cv::putText(overlay, std::to_string(i + 1), c + cv::Point(14, -14),
                cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(0, 255, 0), 2);
  }
  return overlay;
}

}  // namespace

std::optional<std::string> ColorTuningOptions::Check() const {
  if (!(dot_radius_px >= 0.0))
    return "dot_radius_px must be >= 0 (0: estimate)";
  return std::nullopt;
}

ColorTuning TuneColor(const cv::Mat& bgr, const HsvRange& range,
                      const ColorTuningOptions& options) {
  SOFTBENCH_CHECK(!options.Check()) << *options.Check();
  SOFTBENCH_CHECK(bgr.type() == CV_8UC3) << "TuneColor takes 8-bit BGR";
  ColorTuning tuning;
  tuning.mask = ColorMask(bgr, range);
  tuning.segmentation.dot_radius_px = options.dot_radius_px > 0.0
                                          ? options.dot_radius_px
                                          : EstimateDotRadius(tuning.mask);
  if (tuning.segmentation.dot_radius_px < 1.5) {
    tuning.why_not = fmt::format(
        "no dot-sized blobs with hue {}..{}, saturation >= {}, value >= {}",
        range.hue_low, range.hue_high, range.saturation_low, range.value_low);
    return tuning;
  }
  tuning.found = true;
  CleanMask(tuning.segmentation, &tuning.mask);
  tuning.blobs = FindBlobs(tuning.mask, tuning.segmentation);
  const double radius = tuning.segmentation.dot_radius_px;
  tuning.learned = LearnFromDots(bgr, tuning.mask, tuning.blobs, radius);
  tuning.overlay = Overlay(bgr, tuning.mask, tuning.blobs, radius);
  return tuning;
}

}  // namespace softbench
