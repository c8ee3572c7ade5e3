// The tag's image model (vision/tag_image_model.h): its analytic Jacobian
// against central differences of its residuals.
#include "vision/tag_image_model.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <vector>

namespace softbench {
namespace {

// The residuals at `params` (data zero: they are the model's levels).
std::vector<double> Residuals(const TagImageCost& cost,
                              const std::array<double, kTagNumParams>& p) {
  std::vector<double> r(cost.num_residuals());
  const double* blocks[1] = {p.data()};
  EXPECT_TRUE(cost.Evaluate(blocks, r.data(), nullptr));
  return r;
}

// A tag of 9 px cells, tilted and in perspective, blurred, curved and
// sharpened (no code clipped), through `encoding`.
void CheckJacobian(const LumaEncoding& encoding, int depth) {
  const TagBitmap bitmap = Tag36h11Bitmap(7);
  const cv::Mat luma = cv::Mat::zeros(200, 220, depth);
  std::array<double, kTagNumParams> p{};
  // Border corners: bottom-left, bottom-right, top-right, top-left.
  const double corners[8] = {62.3,  140.1, 135.7, 143.9,
                             131.2, 71.4,  58.8,  66.2};
  std::copy(corners, corners + 8, p.begin());
  p[kTagBlur] = 0.7;
  p[kTagInk] = 0.06;
  p[kTagPaper] = 0.45;
  p[kTagTable] = 0.15;
  p[kTagGainU] = 0.02;
  p[kTagGainV] = -0.03;
  p[kTagToneCurve] = 0.4;
  p[kTagSharpenRadius] = 1.3;
  p[kTagSharpenAmount] = 0.4;
  p[kTagPixelFilter] = 0.08;
  TagImageCost cost(luma, bitmap, cv::Rect(20, 20, 170, 160), encoding);
  std::array<double, kTagNumParams> start = p;
  cost.Start(0.5, start.data());  // chooses the pixels; levels from data
  ASSERT_GT(cost.num_residuals(), 5000);
  const int n = cost.num_residuals();
  std::vector<double> residuals(n), jacobian(n * kTagNumParams);
  const double* blocks[1] = {p.data()};
  double* jacobians[1] = {jacobian.data()};
  ASSERT_TRUE(cost.Evaluate(blocks, residuals.data(), jacobians));
  EXPECT_EQ(residuals, Residuals(cost, p));
  for (int j = 0; j < kTagNumParams; ++j) {
    const double step = j < kTagBlur ? 1e-4 : 1e-6;
    std::array<double, kTagNumParams> plus = p, minus = p;
    plus[j] += step;
    minus[j] -= step;
    const std::vector<double> r_plus = Residuals(cost, plus);
    const std::vector<double> r_minus = Residuals(cost, minus);
    double largest = 0.0, worst = 0.0;
    for (int i = 0; i < n; ++i) {
      const double numeric = (r_plus[i] - r_minus[i]) / (2 * step);
      largest = std::max(largest, std::abs(numeric));
      worst =
          std::max(worst, std::abs(jacobian[i * kTagNumParams + j] - numeric));
    }
    EXPECT_GT(largest, 0.0) << "parameter " << j;
    EXPECT_LT(worst, 1e-6 * largest) << "parameter " << j;
  }
}

TEST(TagImageCost, JacobianMatchesCentralDifferencesInSdr) {
  CheckJacobian(LumaEncoding{.transfer = Transfer::kSdr, .full_range = false},
                CV_8U);
}

TEST(TagImageCost, JacobianMatchesCentralDifferencesInHlg) {
  CheckJacobian(
      LumaEncoding{
          .transfer = Transfer::kHlg, .full_range = false, .deep_bits = 10},
      CV_16U);
}

}  // namespace
}  // namespace softbench
