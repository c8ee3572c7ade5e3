#include "vision/frame_source.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <utility>

namespace softbench {

cv::Rect BoxAround(const std::vector<Eigen::Vector2d>& points, double margin_px,
                   const cv::Size& size) {
  if (points.empty()) return {};
  Eigen::Vector2d low = points.front(), high = low;
  for (const Eigen::Vector2d& p : points) {
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  return cv::Rect(
             cv::Point(static_cast<int>(std::floor(low.x() - margin_px)),
                       static_cast<int>(std::floor(low.y() - margin_px))),
             cv::Point(static_cast<int>(std::ceil(high.x() + margin_px)),
                       static_cast<int>(std::ceil(high.y() + margin_px)))) &
         cv::Rect(cv::Point(0, 0), size);
}

ImageFrameSource::ImageFrameSource(cv::Mat bgr, double time_s)
    : bgr_(std::move(bgr)), time_s_(time_s) {
  cv::cvtColor(bgr_, luma_, cv::COLOR_BGR2GRAY);
}

cv::Mat ImageFrameSource::BgrRegion(const cv::Rect& region) const {
  const cv::Rect clipped = region & cv::Rect(0, 0, bgr_.cols, bgr_.rows);
  if (clipped.empty()) return {};
  return bgr_(clipped);
}

cv::Mat ImageFrameSource::BgrRegionReduced(const cv::Rect& region,
                                           const cv::Size& size) const {
  const cv::Rect clipped = region & cv::Rect(0, 0, bgr_.cols, bgr_.rows);
  if (clipped.empty() || size.empty()) return {};
  cv::Mat reduced;
  cv::resize(bgr_(clipped), reduced, size, 0, 0, cv::INTER_AREA);
  return reduced;
}

}  // namespace softbench
