#include "vision/dot_centre.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <opencv2/imgproc.hpp>
#include <random>

#include "vision/color_transfer.h"

namespace softbench {
namespace {

// Linear light (8-bit levels) of a BT.709 code (8-bit levels).
double Light(double code) { return 255 * ToLinear(Transfer::kSdr, code / 255); }

// The light of the background (code 200) less the dot's (code 80).
const double kContrast = Light(200.0) - Light(80.0);

// What a phone does to the codes after its curve: its own S tone curve
// (strength 0..1) and unsharp-mask sharpening (as `render --tone-curve`,
// `--sharpen`).
struct PhoneCodes {
  double tone_curve = 0.0;
  double sharpen_radius_px = 1.0;
  double sharpen_amount = 0.0;
};

// A dark disk on a lighter background under a lighting gradient (which
// multiplies both), each pixel the exact area average (16 x 16 subsamples)
// of light, encoded with the BT.709 curve as a camera does, then `phone`'s
// processing, plus Gaussian noise in codes.
cv::Mat Disk(const Eigen::Vector2d& centre, double radius, double noise,
             std::mt19937* rng, const PhoneCodes& phone = {}) {
  cv::Mat codes(64, 64, CV_32FC1);
  const double k = phone.tone_curve;
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
      const double code = FromLinear(Transfer::kSdr, light / 255);
      codes.at<float>(y, x) = static_cast<float>(
          255 * ((1 - k) * code + k * code * code * (3 - 2 * code)));
    }
  }
  if (phone.sharpen_amount > 0.0) {
    cv::Mat soft;
    cv::GaussianBlur(codes, soft, cv::Size(), phone.sharpen_radius_px);
    cv::addWeighted(codes, 1.0 + phone.sharpen_amount, soft,
                    -phone.sharpen_amount, 0.0, codes);
  }
  cv::Mat image(64, 64, CV_8UC1);
  // Scaled by hand: a distribution of zero spread breaks its precondition
  // (libstdc++ asserts it), and the noise-free images draw the same numbers.
  std::normal_distribution<double> gauss;
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      const double level = codes.at<float>(y, x) + noise * gauss(*rng);
      image.at<uint8_t>(y, x) =
          static_cast<uint8_t>(std::clamp(std::lround(level), 0L, 255L));
    }
  }
  return image;
}

// The worst error of LocateDotCentre over an 8 x 8 grid of the dot's
// sub-pixel phases, noise-free.
double WorstOverPhases(double radius, const PhoneCodes& phone,
                       const DotCentreOptions& options) {
  std::mt19937 rng(3);
  double worst = 0.0;
  for (int i = 0; i < 8; ++i) {
    for (int j = 0; j < 8; ++j) {
      const Eigen::Vector2d truth(32 + (i + 0.25) / 8, 31 + (j + 0.6) / 8);
      const DotCentre c =
          LocateDotCentre(Disk(truth, radius, 0.0, &rng, phone),
                          truth + Eigen::Vector2d(0.4, -0.3), radius, options);
      EXPECT_TRUE(c.found) << c.why_not;
      worst = std::max(worst, (c.centre - truth).norm());
    }
  }
  return worst;
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

// A pixel-sharp dot (each pixel the exact average of its area's light, as
// no lens leaves it) the thesis's size at 1080p (6 px radius), its codes bent
// by a phone's tone curve and sharpened. The light its codes name overshoots
// and undershoots about the edge, unevenly with where the edge falls on the
// pixel grid, and moves the light's centroid; the codes' centroid, which
// sharpening (linear in the codes) leaves where it was, keeps only the
// curve's bend of the edge's partly covered pixels. Without the processing,
// the light is the better of the two (docs/measurement.md).
TEST(LocateDotCentre, WeighingCodesKeepsSharpeningOutOfTheCentre) {
  const PhoneCodes phone{
      .tone_curve = 0.6, .sharpen_radius_px = 1.5, .sharpen_amount = 1.0};
  DotCentreOptions light, codes;
  codes.weigh_codes = true;
  const double light_sharpened = WorstOverPhases(6.0, phone, light);
  const double codes_sharpened = WorstOverPhases(6.0, phone, codes);
  const double light_plain = WorstOverPhases(6.0, {}, light);
  const double codes_plain = WorstOverPhases(6.0, {}, codes);
  std::cout << "worst over the pixel phases, sharpened: light "
            << light_sharpened << " px, codes " << codes_sharpened
            << " px; plain: light " << light_plain << " px, codes "
            << codes_plain << " px\n";
  EXPECT_GT(light_sharpened, 0.04);
  EXPECT_LT(codes_sharpened, 0.4 * light_sharpened);
  EXPECT_LT(light_plain, 0.01);
  EXPECT_LT(codes_plain, 0.02);
}

}  // namespace
}  // namespace softbench
