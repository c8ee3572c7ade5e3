#ifndef SOFTBENCH_VISION_LUMA_H_
#define SOFTBENCH_VISION_LUMA_H_

#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "vision/color_transfer.h"

namespace softbench {

// Luma comes as CV_8UC1 (8-bit video, images) or CV_16UC1 (10 and 12-bit
// video as decoded, 16-bit renders; LumaEncoding::deep_bits says which).
// Measurements read it in 8-bit levels, so their thresholds mean the same
// for every depth, and keep the deeper video's fractions of a level.
inline double LevelsPerCode(int depth, const LumaEncoding& encoding) {
  return depth == CV_8U ? 1.0 : std::ldexp(1.0, 8 - encoding.deep_bits);
}

// Calls `f` with a value of the luma's sample type (uint8_t or uint16_t), for
// code templated on it.
template <typename F>
decltype(auto) WithLumaType(const cv::Mat& luma, F&& f) {
  CV_Assert(luma.type() == CV_8UC1 || luma.type() == CV_16UC1);
  if (luma.depth() == CV_16U) return f(uint16_t{});
  return f(uint8_t{});
}

// Bilinear interpolation of `value` (of a pixel's luma of type T) at (u, v),
// OpenCV's pixel convention; -1 outside the image.
template <typename T, typename F>
double InterpolateLuma(const cv::Mat& luma, double u, double v, F value) {
  const int x = static_cast<int>(std::floor(u)),
            y = static_cast<int>(std::floor(v));
  if (x < 0 || y < 0 || x + 1 >= luma.cols || y + 1 >= luma.rows) return -1.0;
  const double a = u - x, b = v - y;
  const T* r0 = luma.ptr<T>(y) + x;
  const T* r1 = luma.ptr<T>(y + 1) + x;
  return (1 - b) * ((1 - a) * value(r0[0]) + a * value(r0[1])) +
         b * ((1 - a) * value(r1[0]) + a * value(r1[1]));
}

// Bilinear sample of luma of type T at (u, v) in 8-bit levels, its codes
// `levels_per_code` levels each (LevelsPerCode); -1 outside.
template <typename T>
double SampleLuma(const cv::Mat& luma, double u, double v,
                  double levels_per_code) {
  return InterpolateLuma<T>(luma, u, v,
                            [&](T code) { return levels_per_code * code; });
}

// Luma as 8 bits (a view when it is already), for detectors that take only
// 8 bits (libapriltag's quads, OpenCV's checkerboard finder); measurement
// refines on the full-precision luma afterwards.
inline cv::Mat LumaAs8Bit(const cv::Mat& luma, const LumaEncoding& encoding) {
  if (luma.depth() == CV_8U) return luma;
  cv::Mat out;
  luma.convertTo(out, CV_8U, LevelsPerCode(luma.depth(), encoding));
  return out;
}

// Luma whose 16-bit codes fill 16 bits (a view when they do already), for
// code that reads deeper luma that way (OpenCV's checkerboard refinement).
inline cv::Mat LumaFilling16Bits(const cv::Mat& luma,
                                 const LumaEncoding& encoding) {
  if (luma.depth() == CV_8U || encoding.deep_bits == 16) return luma;
  cv::Mat out;
  luma.convertTo(out, CV_16U, std::ldexp(1.0, 16 - encoding.deep_bits));
  return out;
}

// Luma as float in 8-bit levels, into `out` (reused when it has the size).
inline void LumaAsFloat(const cv::Mat& luma, const LumaEncoding& encoding,
                        cv::Mat* out) {
  luma.convertTo(*out, CV_32F, LevelsPerCode(luma.depth(), encoding));
}

// Luma as linear light: each code through `linear` (LinearLumaTable), into
// `out` as CV_32FC1 (which keeps its buffer when it is already that size
// and type, or a view into a larger one, for code that converts a region
// of every frame).
inline void LinearLuma(const cv::Mat& luma, const std::vector<float>& linear,
                       cv::Mat* out) {
  out->create(luma.size(), CV_32FC1);
  WithLumaType(luma, [&](auto code) {
    using T = decltype(code);
    for (int y = 0; y < luma.rows; ++y) {
      const T* in = luma.ptr<T>(y);
      float* o = out->ptr<float>(y);
      for (int x = 0; x < luma.cols; ++x) o[x] = linear[in[x]];
    }
  });
}

inline cv::Mat LinearLuma(const cv::Mat& luma,
                          const std::vector<float>& linear) {
  cv::Mat out;
  LinearLuma(luma, linear, &out);
  return out;
}

}  // namespace softbench

#endif  // SOFTBENCH_VISION_LUMA_H_
