// A phone's temporal noise reduction as render draws it (issue 28).
#include "pipelines/synthetic/temporal_denoiser.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>

namespace softbench {
namespace {

// A flat 16-bit frame at `level` (8-bit levels) with Gaussian noise of
// `sigma` levels, seeded.
cv::Mat NoisyFlat(double level, double sigma, uint64_t seed) {
  cv::Mat noise(64, 64, CV_32FC3);
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::NORMAL, level, sigma);
  cv::Mat frame;
  noise.convertTo(frame, CV_16UC3, 257.0);
  return frame;
}

double Variance(const cv::Mat& frame) {
  cv::Mat levels;
  frame.convertTo(levels, CV_64FC3, 1.0 / 257.0);
  cv::Scalar mean, deviation;
  cv::meanStdDev(levels.reshape(1), mean, deviation);
  return deviation[0] * deviation[0];
}

// In a still scene the recursive blend keeps part of the previous frame:
// at strength 0.5 the noise's variance would fall to a third; a noise step
// of the threshold's size counts partly as motion, which leaves about half
// (0.56 here). The mean stays.
TEST(TemporalDenoiser, StillRegionsLoseNoise) {
  TemporalDenoiseOptions options;
  options.strength = 0.5;
  TemporalDenoiser denoiser(options);
  double variance_in = 0.0, variance_out = 0.0, mean_out = 0.0;
  const int frames = 60;
  for (int k = 0; k < frames; ++k) {
    cv::Mat frame = NoisyFlat(100.0, 1.0, 7 + k);
    const double before = Variance(frame);
    denoiser.Apply(&frame);
    if (k < 10) continue;  // the filter's start
    variance_in += before / (frames - 10);
    variance_out += Variance(frame) / (frames - 10);
    mean_out += cv::mean(frame)[0] / 257.0 / (frames - 10);
  }
  EXPECT_NEAR(variance_in, 1.0, 0.05);
  EXPECT_LT(variance_out, 0.65);
  EXPECT_GT(variance_out, 0.3);
  EXPECT_NEAR(mean_out, 100.0, 0.05);
}

// What moves by far more than the threshold passes unchanged: no ghost of
// the previous frame; the first frame passes as it is.
TEST(TemporalDenoiser, MotionPassesUnchanged) {
  TemporalDenoiseOptions options;
  options.strength = 0.9;
  TemporalDenoiser denoiser(options);
  cv::Mat first(32, 32, CV_8UC3, cv::Scalar(50, 50, 50));
  denoiser.Apply(&first);
  EXPECT_EQ(first.at<cv::Vec3b>(5, 5), cv::Vec3b(50, 50, 50));
  cv::Mat second = first.clone();
  second(cv::Rect(0, 0, 16, 32)).setTo(cv::Scalar(200, 60, 200));
  const cv::Mat expected = second.clone();
  denoiser.Apply(&second);
  EXPECT_EQ(cv::norm(second, expected, cv::NORM_INF), 0.0);
}

TEST(TemporalDenoiseOptions, SaysWhatIsWrong) {
  TemporalDenoiseOptions options;
  EXPECT_FALSE(options.Problem().has_value());
  options.strength = 1.0;
  EXPECT_EQ(options.Problem(),
            "temporal noise reduction's strength must be 0..0.95");
  options.strength = 0.5;
  options.motion_threshold_dn = 0.0;
  EXPECT_TRUE(options.Problem().has_value());
}

}  // namespace
}  // namespace softbench
