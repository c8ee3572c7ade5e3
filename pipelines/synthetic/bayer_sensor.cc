#include "pipelines/synthetic/bayer_sensor.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include "util/check.h"

namespace softbench {

std::optional<std::string> BayerSensorOptions::Problem() const {
  if (!(full_well_e == 0.0 || (full_well_e >= 100.0 && full_well_e <= 1e6))) {
    return "the sensor's full well must be 0 (no shot noise) or 100..1e6 "
           "electrons";
  }
  if (!(read_noise_e >= 0.0 && read_noise_e <= 100.0)) {
    return "the sensor's read noise must be 0..100 electrons";
  }
  if (demosaic == Demosaic::kNone &&
      (full_well_e > 0.0 || read_noise_e > 0.0)) {
    return "the sensor's noise needs a colour filter (--bayer)";
  }
  if (read_noise_e > 0.0 && full_well_e == 0.0) {
    return "the sensor's read noise needs its full well (electrons at white)";
  }
  return std::nullopt;
}

std::optional<Demosaic> ParseDemosaic(const std::string& name) {
  if (name == "bilinear") return Demosaic::kBilinear;
  if (name == "edge-aware") return Demosaic::kEdgeAware;
  return std::nullopt;
}

cv::Mat ThroughBayerSensor(const cv::Mat& light,
                           const BayerSensorOptions& options, uint64_t seed) {
  SOFTBENCH_CHECK(light.type() == CV_32FC3) << "light must be CV_32FC3";
  SOFTBENCH_CHECK(options.demosaic != Demosaic::kNone && !options.Problem())
      << "a Bayer sensor needs a demosaic and valid options";
  // RGGB: red on even rows and columns, blue on odd ones, green between
  // (BGR channel indices 2, 1, 0).
  const auto channel = [](int row, int col) {
    return row % 2 == 0 ? (col % 2 == 0 ? 2 : 1) : (col % 2 == 0 ? 1 : 0);
  };
  cv::Mat raw(light.size(), CV_16UC1);
  // Fixed stripes, each with its own seeded generator: the same frame for
  // any number of threads.
  constexpr int kStripes = 32;
  const double well = options.full_well_e;
  cv::parallel_for_(cv::Range(0, kStripes), [&](const cv::Range& range) {
    for (int s = range.start; s < range.end; ++s) {
      const int begin = light.rows * s / kStripes;
      const int end = light.rows * (s + 1) / kStripes;
      cv::RNG rng(seed * 0x9E3779B97F4A7C15ULL + s + 1);
      for (int v = begin; v < end; ++v) {
        const auto* in = light.ptr<cv::Vec3f>(v);
        auto* out = raw.ptr<uint16_t>(v);
        for (int u = 0; u < light.cols; ++u) {
          double x = std::clamp<double>(in[u][channel(v, u)], 0.0, 1.0);
          if (well > 0.0) {
            const double electrons = x * well;
            const double sigma = std::sqrt(
                electrons + options.read_noise_e * options.read_noise_e);
            x = (electrons + sigma * rng.gaussian(1.0)) / well;
          }
          out[u] = cv::saturate_cast<uint16_t>(x * 65535.0);
        }
      }
    }
  });
  // OpenCV names a Bayer pattern by the second row's second and third
  // pixels: RGGB from (0, 0) is its "BG" (docs of cv::demosaicing).
  cv::Mat demosaiced;
  cv::demosaicing(raw, demosaiced,
                  options.demosaic == Demosaic::kEdgeAware
                      ? cv::COLOR_BayerBG2BGR_EA
                      : cv::COLOR_BayerBG2BGR);
  cv::Mat result;
  demosaiced.convertTo(result, CV_32FC3, 1.0 / 65535.0);
  return result;
}

}  // namespace softbench
