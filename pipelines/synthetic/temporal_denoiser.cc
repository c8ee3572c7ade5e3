#include "pipelines/synthetic/temporal_denoiser.h"

#include <cmath>
#include <opencv2/core/utility.hpp>

#include "util/check.h"

namespace softbench {

std::optional<std::string> TemporalDenoiseOptions::Problem() const {
  if (!(strength >= 0.0 && strength <= 0.95)) {
    return "temporal noise reduction's strength must be 0..0.95";
  }
  if (!(motion_threshold_dn > 0.0 && motion_threshold_dn <= 255.0)) {
    return "temporal noise reduction's motion threshold must be 0..255 "
           "levels, above 0";
  }
  return std::nullopt;
}

TemporalDenoiser::TemporalDenoiser(const TemporalDenoiseOptions& options)
    : options_(options) {
  SOFTBENCH_CHECK(!options_.Problem()) << *options_.Problem();
}

void TemporalDenoiser::Apply(cv::Mat* frame) {
  SOFTBENCH_CHECK(frame->type() == CV_8UC3 || frame->type() == CV_16UC3)
      << "temporal noise reduction takes 8 or 16-bit colour frames";
  if (options_.strength == 0.0) return;
  const bool sixteen = frame->type() == CV_16UC3;
  const double to_levels = sixteen ? 1.0 / 257.0 : 1.0;
  cv::Mat current;
  frame->convertTo(current, CV_32FC3, to_levels);
  if (previous_.empty() || previous_.size() != current.size()) {
    previous_ = current;
    return;
  }
  // The motion test on the pixel's largest channel difference, so a
  // coloured edge moving counts as motion in every channel alike.
  const float strength = static_cast<float>(options_.strength);
  const float inverse_threshold =
      static_cast<float>(1.0 / options_.motion_threshold_dn);
  current.forEach<cv::Vec3f>([&](cv::Vec3f& c, const int* at) {
    const cv::Vec3f& p = previous_.at<cv::Vec3f>(at[0], at[1]);
    const cv::Vec3f d = c - p;
    const float largest =
        std::max({std::abs(d[0]), std::abs(d[1]), std::abs(d[2])}) *
        inverse_threshold;
    const float w = strength * std::exp(-largest * largest);
    c -= w * d;
  });
  previous_ = current;
  current.convertTo(*frame, frame->type(), 1.0 / to_levels);
}

}  // namespace softbench
