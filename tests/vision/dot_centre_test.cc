#include "vision/dot_centre.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "vision/color_transfer.h"

namespace softbench {
namespace {

// Linear light (8-bit levels) of a BT.709 code (8-bit levels).
double Light(double code) { return 255 * ToLinear(Transfer::kSdr, code / 255); }

// The light of the background (code 200) less the dot's (code 80).
const double kContrast = Light(200.0) - Light(80.0);

// A dark disk on a lighter background under a lighting gradient (which
// multiplies both), each pixel the exact area average (16 x 16 subsamples)
// of light, encoded with the BT.709 curve as a camera does, plus Gaussian
// noise in codes.
cv::Mat Disk(const Eigen::Vector2d& centre, double radius, double noise,
             std::mt19937* rng) {
  cv::Mat image(64, 64, CV_8UC1);
  std::normal_distribution<double> gauss(0.0, noise);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      int inside = 0;
      for (int j = 0; j < 16; ++j) {
        for (int i = 0; i < 16; ++i) {
          const double u = x - 0.5 + (i + 0.5) / 16,
                       v = y - 0.5 + (j + 0.5) / 16;
          inside += std::hypot(u - centre.x(), v - centre.y()) <= radius;
        }
      }
      const double gain = 1.0 + 0.0015 * x;  // 10 % across the image
      const double light = gain * (Light(200.0) - kContrast * inside / 256.0);
      const double level =
          255 * FromLinear(Transfer::kSdr, light / 255) + gauss(*rng);
      image.at<uint8_t>(y, x) =
          static_cast<uint8_t>(std::clamp(std::lround(level), 0L, 255L));
    }
  }
  return image;
}

TEST(LocateDotCentre, SubPixelCentresWithHonestUncertainty) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> offset(-0.5, 0.5);
  double sum_sq = 0.0, sum_sigma_sq = 0.0;
  const int n = 40;
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector2d truth(32 + offset(rng), 31 + offset(rng));
    const cv::Mat image = Disk(truth, 9.0, 1.0, &rng);
    // Start a pixel away, as a chroma-blurred mask would.
    const DotCentre c =
        LocateDotCentre(image, truth + Eigen::Vector2d(0.8, -0.7), 9.0);
    ASSERT_TRUE(c.found) << c.why_not;
    sum_sq += (c.centre - truth).squaredNorm() / 2;
    sum_sigma_sq += c.sigma_px * c.sigma_px;
    EXPECT_NEAR(c.contrast, kContrast * (1.0 + 0.0015 * truth.x()), 2.0);
  }
  const double rms = std::sqrt(sum_sq / n), sigma = std::sqrt(sum_sigma_sq / n);
  EXPECT_LT(rms, 0.02);
  // The reported uncertainty matches the scatter (noise 1 level).
  EXPECT_GT(sigma, 0.5 * rms);
  EXPECT_LT(sigma, 2.0 * rms);
}

TEST(LocateDotCentre, ReportsWhyNot) {
  std::mt19937 rng(1);
  cv::Mat flat(64, 64, CV_8UC1, cv::Scalar(200));
  const DotCentre none = LocateDotCentre(flat, {32, 32}, 9.0);
  EXPECT_FALSE(none.found);
  EXPECT_NE(none.why_not.find("luma contrast"), std::string::npos)
      << none.why_not;
  const DotCentre edge =
      LocateDotCentre(Disk({8, 32}, 9.0, 0.0, &rng), {8, 32}, 9.0);
  EXPECT_FALSE(edge.found);
  EXPECT_EQ(edge.why_not, "too close to the image border");
}

}  // namespace
}  // namespace softbench
