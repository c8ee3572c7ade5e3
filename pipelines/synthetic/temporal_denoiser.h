#ifndef SOFTBENCH_PIPELINES_SYNTHETIC_TEMPORAL_DENOISER_H_
#define SOFTBENCH_PIPELINES_SYNTHETIC_TEMPORAL_DENOISER_H_

#include <opencv2/core.hpp>
#include <optional>
#include <string>

namespace softbench {

// A phone's temporal noise reduction on still regions (issue 28): each
// frame's codes are blended with the previous output where they differ by
// little (noise), and kept where they differ by much (motion).
struct TemporalDenoiseOptions {
  // The previous output's weight where nothing moves, in [0, 0.95]: 0 is
  // none; 0.5 leaves a third of the noise's variance in still regions.
  double strength = 0.0;
  // The difference [8-bit levels] at which the blend falls to 1/e of
  // `strength`: differences well above it count as motion.
  double motion_threshold_dn = 3.0;

  std::optional<std::string> Problem() const;
};

class TemporalDenoiser {
 public:
  explicit TemporalDenoiser(const TemporalDenoiseOptions& options);

  // Denoises `frame` (CV_8UC3, or CV_16UC3 with 65535 = white) in place
  // against the previous frame given; the first frame passes unchanged.
  void Apply(cv::Mat* frame);

 private:
  TemporalDenoiseOptions options_;
  cv::Mat previous_;  // CV_32FC3 in 8-bit levels, unquantised
};

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_SYNTHETIC_TEMPORAL_DENOISER_H_
