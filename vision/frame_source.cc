#include "vision/frame_source.h"

#include <opencv2/imgproc.hpp>

namespace softbench {

ImageFrameSource::ImageFrameSource(const cv::Mat& bgr, double time_s)
    : bgr_(bgr), time_s_(time_s) {
  cv::cvtColor(bgr_, luma_, cv::COLOR_BGR2GRAY);
}

cv::Mat ImageFrameSource::BgrRegion(const cv::Rect& region) const {
  const cv::Rect clipped = region & cv::Rect(0, 0, bgr_.cols, bgr_.rows);
  if (clipped.empty()) return {};
  return bgr_(clipped);
}

}  // namespace softbench
