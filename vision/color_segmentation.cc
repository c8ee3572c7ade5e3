#include "vision/color_segmentation.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>

#include "util/statistics.h"
#include "vision/mask_morphology.h"

namespace softbench {

HsvRange HsvRange::FromBounds(const std::array<int, 6>& b) {
  return {b[0], b[1], b[2], b[3], b[4], b[5]};
}

bool HsvRange::Contains(const cv::Vec3b& hsv) const {
  const bool hue = Wraps() ? (hsv[0] >= hue_low || hsv[0] <= hue_high)
                           : (hsv[0] >= hue_low && hsv[0] <= hue_high);
  return hue && hsv[1] >= saturation_low && hsv[1] <= saturation_high &&
         hsv[2] >= value_low && hsv[2] <= value_high;
}

std::optional<std::string> SegmentationOptions::Problem() const {
  if (!(dot_radius_px >= 1.5)) {
    return fmt::format(
        "the expected dot radius is {:.2f} px; dots need a radius of at "
        "least 1.5 px (use a larger dot or a closer camera)",
        dot_radius_px);
  }
  if (!(morphology_fraction >= 0.0 && morphology_fraction < 1.0)) {
    return "morphology_fraction must be in [0, 1)";
  }
  if (!(min_area_fraction > 0.0 && max_area_fraction > min_area_fraction)) {
    return "area fractions must satisfy 0 < min < max";
  }
  if (!(min_circularity >= 0.0 && min_circularity <= 1.0) ||
      !(min_fill >= 0.0 && min_fill <= 1.0)) {
    return "min_circularity and min_fill must be in [0, 1]";
  }
  return std::nullopt;
}

cv::Mat ColorMask(const cv::Mat& bgr, const HsvRange& range) {
  cv::Mat hsv;
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  // One pass of the range's own test: a hue range that wraps through 0 took
  // two cv::inRange passes and their union, three times the test's cost
  // on a tracked dot's region.
  cv::Mat mask(hsv.size(), CV_8UC1);
  for (int y = 0; y < hsv.rows; ++y) {
    const auto* in = hsv.ptr<cv::Vec3b>(y);
    auto* out = mask.ptr<uint8_t>(y);
    for (int x = 0; x < hsv.cols; ++x) out[x] = range.Contains(in[x]) ? 255 : 0;
  }
  return mask;
}

void CleanMask(const SegmentationOptions& options, cv::Mat* mask) {
  const int r =
      std::max(1, static_cast<int>(std::lround(options.morphology_fraction *
                                               options.dot_radius_px)));
  OpenThenClose(r, mask);
}

BlobSummary FindBlobs(const cv::Mat& mask, const SegmentationOptions& options,
                      const cv::Point& offset) {
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids,
                                                 8, CV_32S);
  // Second central moments of every component in one pass over the labels
  // (about each component's centroid).
  std::vector<double> spread(n, 0.0);
  for (int y = 0; y < labels.rows; ++y) {
    const int* row = labels.ptr<int>(y);
    for (int x = 0; x < labels.cols; ++x) {
      const int i = row[x];
      if (i == 0) continue;
      const double dx = x - centroids.at<double>(i, 0),
                   dy = y - centroids.at<double>(i, 1);
      spread[i] += dx * dx + dy * dy;
    }
  }
  const double expected =
      std::numbers::pi * options.dot_radius_px * options.dot_radius_px;
  BlobSummary summary;
  for (int i = 1; i < n; ++i) {
    const double area = stats.at<int>(i, cv::CC_STAT_AREA);
    if (area < options.min_area_fraction * expected ||
        area > options.max_area_fraction * expected) {
      ++summary.rejected_area;
      continue;
    }
    const cv::Rect box(stats.at<int>(i, cv::CC_STAT_LEFT),
                       stats.at<int>(i, cv::CC_STAT_TOP),
                       stats.at<int>(i, cv::CC_STAT_WIDTH),
                       stats.at<int>(i, cv::CC_STAT_HEIGHT));
    Blob blob;
    blob.area_px = area;
    // A disk's polar moment is area^2 / (2 pi); each pixel adds its own
    // 1/6 px^2 (a unit square about its centre).
    blob.circularity = std::min(
        1.0, area * area / (2.0 * std::numbers::pi * (spread[i] + area / 6.0)));
    blob.fill = area / box.area();
    if (blob.circularity < options.min_circularity ||
        blob.fill < options.min_fill) {
      ++summary.rejected_shape;
      continue;
    }
    blob.centroid = Eigen::Vector2d(centroids.at<double>(i, 0) + offset.x,
                                    centroids.at<double>(i, 1) + offset.y);
    blob.box = box + offset;
    summary.accepted.push_back(blob);
  }
  return summary;
}

std::optional<Blob> SingleBlob(const cv::Mat& mask,
                               const SegmentationOptions& options,
                               const cv::Point& offset) {
  const cv::Moments m = cv::moments(mask, true);
  const double area = m.m00;
  const double expected =
      std::numbers::pi * options.dot_radius_px * options.dot_radius_px;
  if (area < options.min_area_fraction * expected ||
      area > options.max_area_fraction * expected) {
    return std::nullopt;
  }
  const cv::Rect box = cv::boundingRect(mask);
  if (box.x == 0 || box.y == 0 || box.br().x == mask.cols ||
      box.br().y == mask.rows) {
    return std::nullopt;
  }
  Blob blob;
  blob.area_px = area;
  // As in FindBlobs: area^2 / (2 pi polar moment), pixels' own 1/6 px^2.
  blob.circularity = std::min(
      1.0,
      area * area / (2.0 * std::numbers::pi * (m.mu20 + m.mu02 + area / 6.0)));
  blob.fill = area / box.area();
  if (blob.circularity < options.min_circularity ||
      blob.fill < options.min_fill) {
    return std::nullopt;
  }
  blob.centroid =
      Eigen::Vector2d(m.m10 / area + offset.x, m.m01 / area + offset.y);
  blob.box = box + offset;
  return blob;
}

double EstimateDotRadius(const cv::Mat& mask) {
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids,
                                                 8, CV_32S);
  std::vector<double> radii;
  for (int i = 1; i < n; ++i) {
    const int area = stats.at<int>(i, cv::CC_STAT_AREA);
    if (area >= 12) radii.push_back(std::sqrt(area / std::numbers::pi));
  }
  return radii.empty() ? 0.0 : Median(radii);
}

BlobSummary SegmentDots(const cv::Mat& bgr, const HsvRange& range,
                        const SegmentationOptions& options,
                        const cv::Point& offset) {
  cv::Mat mask = ColorMask(bgr, range);
  CleanMask(options, &mask);
  return FindBlobs(mask, options, offset);
}

double MeanHue(const cv::Mat& hsv, const cv::Mat& mask, const cv::Rect& box) {
  double sum_cos = 0.0, sum_sin = 0.0;
  int pixels = 0;
  const cv::Rect inside = box & cv::Rect(0, 0, hsv.cols, hsv.rows);
  for (int y = inside.y; y < inside.y + inside.height; ++y) {
    for (int x = inside.x; x < inside.x + inside.width; ++x) {
      if (mask.at<uint8_t>(y, x) == 0) continue;
      const cv::Vec3b& p = hsv.at<cv::Vec3b>(y, x);
      const double angle = p[0] * std::numbers::pi / 90.0;  // 180 -> 2 pi
      sum_cos += std::cos(angle) * p[1];
      sum_sin += std::sin(angle) * p[1];
      ++pixels;
    }
  }
  if (pixels == 0) return NAN;
  const double hue = std::atan2(sum_sin, sum_cos) * 90.0 / std::numbers::pi;
  return hue < 0.0 ? hue + 180.0 : hue;
}

LearnedHsvRange LearnHsvRange(const cv::Mat& bgr, const cv::Mat& dot_cores,
                              const cv::Mat& dot_regions) {
  cv::Mat hsv;
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  std::vector<double> offsets;  // hue relative to the circular mean
  std::vector<int> saturation, value;
  std::vector<cv::Vec3b> pixels;
  for (int y = 0; y < hsv.rows; ++y) {
    for (int x = 0; x < hsv.cols; ++x) {
      if (dot_cores.at<uint8_t>(y, x) != 0) {
        pixels.push_back(hsv.at<cv::Vec3b>(y, x));
      }
    }
  }
  LearnedHsvRange learned;
  learned.dot_pixels = static_cast<int>(pixels.size());
  if (pixels.empty()) return learned;
  const double mean_hue =
      MeanHue(hsv, dot_cores, cv::Rect(0, 0, hsv.cols, hsv.rows));
  for (const cv::Vec3b& p : pixels) {
    double d = p[0] - mean_hue;
    while (d > 90) d -= 180;
    while (d < -90) d += 180;
    offsets.push_back(d);
    saturation.push_back(p[1]);
    value.push_back(p[2]);
  }
  constexpr double kHueMargin = 4.0, kLevelMargin = 0.75;
  const double low = mean_hue + Quantile(offsets, 0.01) - kHueMargin;
  const double high = mean_hue + Quantile(offsets, 0.99) + kHueMargin;
  const auto wrap = [](double h) {
    const int v = static_cast<int>(std::lround(h));
    return ((v % 180) + 180) % 180;
  };
  HsvRange& r = learned.range;
  if (high - low >= 179) {
    r.hue_low = 0;
    r.hue_high = 179;
  } else {
    r.hue_low = wrap(low);
    r.hue_high = wrap(high);
  }
  r.saturation_low =
      static_cast<int>(kLevelMargin * Quantile(saturation, 0.01));
  r.value_low = static_cast<int>(kLevelMargin * Quantile(value, 0.01));
  int inside = 0;
  for (const cv::Vec3b& p : pixels) inside += r.Contains(p);
  learned.dot_coverage = static_cast<double>(inside) / pixels.size();
  cv::Mat in_range = ColorMask(bgr, r);
  in_range.setTo(0, dot_regions);
  learned.outside_pixels = cv::countNonZero(in_range);
  return learned;
}

}  // namespace softbench
