#ifndef SOFTBENCH_VISION_FRAME_SOURCE_H_
#define SOFTBENCH_VISION_FRAME_SOURCE_H_

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "vision/video_reader.h"

namespace softbench {

// The whole-pixel box holding `points` grown by `margin_px` on every side,
// clipped to an image of `size` (empty when no point is given).
cv::Rect BoxAround(const std::vector<Eigen::Vector2d>& points, double margin_px,
                   const cv::Size& size);

// What measuring one frame reads: its full-resolution luma, which locates
// edges, and the colour of chosen regions, which finds and names dots. A
// video converts only those regions; a still image has it all already.
class FrameSource {
 public:
  virtual ~FrameSource() = default;
  virtual const cv::Mat& luma() const = 0;  // CV_8UC1 or CV_16UC1 (luma.h)
  // BGR (CV_8UC3) of `region` clipped to the frame; empty when outside.
  virtual cv::Mat BgrRegion(const cv::Rect& region) const = 0;
  // BGR of `region` clipped to the frame, resampled to `size` by averaging
  // areas (an overview for finding dots); empty when outside.
  virtual cv::Mat BgrRegionReduced(const cv::Rect& region,
                                   const cv::Size& size) const = 0;
  virtual double time_s() const = 0;
  // How luma's codes encode light (edges are located in linear light).
  virtual LumaEncoding luma_encoding() const = 0;
};

// A BGR image (a rendered frame, a PNG) as a frame; luma is OpenCV's
// BT.601 grey.
class ImageFrameSource : public FrameSource {
 public:
  explicit ImageFrameSource(cv::Mat bgr, double time_s = 0.0);
  const cv::Mat& luma() const override { return luma_; }
  cv::Mat BgrRegion(const cv::Rect& region) const override;
  cv::Mat BgrRegionReduced(const cv::Rect& region,
                           const cv::Size& size) const override;
  double time_s() const override { return time_s_; }
  LumaEncoding luma_encoding() const override { return {}; }  // sRGB ~ SDR

 private:
  cv::Mat bgr_, luma_;
  double time_s_;
};

// The frame a VideoReader last returned (read with want_bgr = false, so
// colour is converted region by region).
class VideoFrameSource : public FrameSource {
 public:
  VideoFrameSource(VideoReader* reader, const VideoFrame* frame)
      : reader_(reader), frame_(frame) {}
  const cv::Mat& luma() const override { return frame_->luma; }
  cv::Mat BgrRegion(const cv::Rect& region) const override {
    return reader_->BgrRegion(region);
  }
  cv::Mat BgrRegionReduced(const cv::Rect& region,
                           const cv::Size& size) const override {
    return reader_->BgrRegionReduced(region, size);
  }
  double time_s() const override { return frame_->time_s; }
  LumaEncoding luma_encoding() const override {
    return reader_->info().luma_encoding();
  }

 private:
  VideoReader* reader_;
  const VideoFrame* frame_;
};

}  // namespace softbench

#endif  // SOFTBENCH_VISION_FRAME_SOURCE_H_
