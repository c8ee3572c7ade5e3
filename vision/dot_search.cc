#include "vision/dot_search.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace softbench {

std::optional<std::string> DotSearchOptions::Problem() const {
  if (!(min_coarse_radius_px >= 1.5)) {
    return "min_coarse_radius_px must be >= 1.5 (smaller dots vanish in the "
           "cleaning)";
  }
  if (max_reduction < 1) return "max_reduction must be >= 1";
  return std::nullopt;
}

int DotSearchReduction(double dot_radius_px, const DotSearchOptions& options) {
  return std::clamp(static_cast<int>(std::floor(dot_radius_px /
                                                options.min_coarse_radius_px)),
                    1, options.max_reduction);
}

namespace {

// `r` grown to even corners (whole 4:2:0 chroma samples, so a video
// converts it straight from its planes), within `bounds`.
cv::Rect EvenCorners(const cv::Rect& r, const cv::Rect& bounds) {
  const int x0 = r.x / 2 * 2, y0 = r.y / 2 * 2;
  const int x1 = (r.br().x + 1) / 2 * 2, y1 = (r.br().y + 1) / 2 * 2;
  return cv::Rect(cv::Point(x0, y0), cv::Point(x1, y1)) & bounds;
}

// Unites overlapping boxes until none overlap, so no blob is segmented in
// two boxes.
void MergeOverlapping(std::vector<cv::Rect>* boxes) {
  for (bool merged = true; merged;) {
    merged = false;
    for (size_t i = 0; i < boxes->size() && !merged; ++i) {
      for (size_t j = i + 1; j < boxes->size(); ++j) {
        if (((*boxes)[i] & (*boxes)[j]).empty()) continue;
        (*boxes)[i] |= (*boxes)[j];
        boxes->erase(boxes->begin() + static_cast<std::ptrdiff_t>(j));
        merged = true;
        break;
      }
    }
  }
}

// Whether `blob` reaches an edge of `box` that is not an edge of `outer`.
bool RunsOut(const Blob& blob, const cv::Rect& box, const cv::Rect& outer) {
  return (blob.box.x <= box.x && box.x > outer.x) ||
         (blob.box.y <= box.y && box.y > outer.y) ||
         (blob.box.br().x >= box.br().x && box.br().x < outer.br().x) ||
         (blob.box.br().y >= box.br().y && box.br().y < outer.br().y);
}

}  // namespace

BlobSummary SearchDots(const FrameSource& frame, const cv::Rect& region,
                       const HsvRange& range,
                       const SegmentationOptions& segmentation,
                       const DotSearchOptions& options) {
  const cv::Rect frame_rect(0, 0, frame.luma().cols, frame.luma().rows);
  const cv::Rect wanted = region & frame_rect;
  if (wanted.empty()) return {};
  const int factor = DotSearchReduction(segmentation.dot_radius_px, options);
  if (factor < 2) {
    return SegmentDots(frame.BgrRegion(wanted), range, segmentation,
                       wanted.tl());
  }
  // The coarse pass covers whole chroma samples; blobs come from `wanted`.
  const cv::Rect searched = EvenCorners(wanted, frame_rect);
  const cv::Size coarse_size((searched.width + factor - 1) / factor,
                             (searched.height + factor - 1) / factor);
  const cv::Mat coarse = frame.BgrRegionReduced(searched, coarse_size);
  if (coarse.empty()) return {};
  // Full-resolution pixels per coarse pixel (the factor, or a little less at
  // an edge that does not divide).
  const double sx = static_cast<double>(searched.width) / coarse_size.width;
  const double sy = static_cast<double>(searched.height) / coarse_size.height;

  SegmentationOptions coarse_options = segmentation;
  coarse_options.dot_radius_px = segmentation.dot_radius_px / factor;
  cv::Mat mask = ColorMask(coarse, range);
  CleanMask(coarse_options, &mask);
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids,
                                                 8, CV_32S);
  // Area bounds twice as loose as the full-resolution filter's: a coarse
  // pixel on a dot's edge is in or out whole.
  const double expected = std::numbers::pi * coarse_options.dot_radius_px *
                          coarse_options.dot_radius_px;
  const double margin = std::ceil(segmentation.dot_radius_px) + factor;
  BlobSummary summary;
  std::vector<cv::Rect> boxes;
  for (int i = 1; i < n; ++i) {
    const int area = stats.at<int>(i, cv::CC_STAT_AREA);
    if (area < 0.5 * segmentation.min_area_fraction * expected ||
        area > 2.0 * segmentation.max_area_fraction * expected) {
      ++summary.rejected_area;
      continue;
    }
    const int left = stats.at<int>(i, cv::CC_STAT_LEFT);
    const int top = stats.at<int>(i, cv::CC_STAT_TOP);
    const int right = left + stats.at<int>(i, cv::CC_STAT_WIDTH);
    const int bottom = top + stats.at<int>(i, cv::CC_STAT_HEIGHT);
    const cv::Point low(
        searched.x + static_cast<int>(std::floor(left * sx - margin)),
        searched.y + static_cast<int>(std::floor(top * sy - margin)));
    const cv::Point high(
        searched.x + static_cast<int>(std::ceil(right * sx + margin)),
        searched.y + static_cast<int>(std::ceil(bottom * sy + margin)));
    boxes.push_back(cv::Rect(low, high) & wanted);
  }
  MergeOverlapping(&boxes);
  for (const cv::Rect& box : boxes) {
    const BlobSummary fine =
        SegmentDots(frame.BgrRegion(box), range, segmentation, box.tl());
    summary.rejected_area += fine.rejected_area;
    summary.rejected_shape += fine.rejected_shape;
    for (const Blob& blob : fine.accepted) {
      if (RunsOut(blob, box, wanted)) {
        ++summary.rejected_shape;
      } else {
        summary.accepted.push_back(blob);
      }
    }
  }
  return summary;
}

}  // namespace softbench
