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

// Circular (mod 180) difference of two OpenCV hues, in -90..90.
double HueDifference(double a, double b) {
  double d = std::fmod(a - b, 180.0);
  if (d > 90.0) d -= 180.0;
  if (d < -90.0) d += 180.0;
  return d;
}

// A blob's hue: the mean hue over its core, where the colour is the dot's own
// (a mask of the blob's box only: a 4K frame's worth per blob is waste).
double BlobHue(const cv::Mat& hsv, const Blob& blob, double radius) {
  const cv::Rect box = blob.box & cv::Rect(0, 0, hsv.cols, hsv.rows);
  cv::Mat core = cv::Mat::zeros(box.size(), CV_8UC1);
  cv::circle(core, Pixel(blob.centroid) - box.tl(),
             std::max(1, static_cast<int>(0.7 * radius)), 255, cv::FILLED);
  return MeanHue(hsv(box), core, cv::Rect(cv::Point(), box.size()));
}

// Splits the accepted blobs by hue: those within max_hue_difference of the
// blob nearest the range's centre stay dots, the others are another colour.
void SplitByHue(const cv::Mat& bgr, const HsvRange& range, double radius,
                double max_difference, ColorTuning* tuning) {
  std::vector<Blob>& blobs = tuning->blobs.accepted;
  if (blobs.size() < 2) return;
  cv::Mat hsv;
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  const double centre = std::fmod(
      range.hue_low + (range.Wraps() ? range.hue_high + 180 - range.hue_low
                                     : range.hue_high - range.hue_low) /
                          2.0,
      180.0);
  std::vector<double> hues;
  for (const Blob& blob : blobs) hues.push_back(BlobHue(hsv, blob, radius));
  size_t nearest = 0;
  for (size_t i = 1; i < hues.size(); ++i) {
    if (std::abs(HueDifference(hues[i], centre)) <
        std::abs(HueDifference(hues[nearest], centre))) {
      nearest = i;
    }
  }
  std::vector<Blob> kept;
  for (size_t i = 0; i < blobs.size(); ++i) {
    if (std::abs(HueDifference(hues[i], hues[nearest])) <= max_difference) {
      kept.push_back(blobs[i]);
    } else {
      tuning->other_hue.push_back(blobs[i]);
      tuning->other_hues.push_back(hues[i]);
    }
  }
  blobs = std::move(kept);
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

std::optional<std::string> ColorTuningOptions::Problem() const {
  // A dot wider than a 4K frame is no dot.
  if (!(dot_radius_px >= 0.0 && dot_radius_px <= 2000.0)) {
    return "dot_radius_px must be 0 (estimate) to 2000 px";
  }
  if (!(max_hue_difference > 0.0 && max_hue_difference < 90.0)) {
    return "max_hue_difference must be in (0, 90)";
  }
  return std::nullopt;
}

ColorTuning TuneColor(const cv::Mat& bgr, const HsvRange& range,
                      const ColorTuningOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
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
  SplitByHue(bgr, range, radius, options.max_hue_difference, &tuning);
  tuning.learned = LearnFromDots(bgr, tuning.mask, tuning.blobs, radius);
  tuning.overlay = Overlay(bgr, tuning.mask, tuning.blobs, radius);
  return tuning;
}

}  // namespace softbench
