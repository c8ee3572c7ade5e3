// The tag's image model (vision/tag_image_model.h): its analytic Jacobian
// against central differences of its residuals, and the normal equations'
// square root that Ceres fits.
#include "vision/tag_image_model.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/LU>
#include <array>
#include <opencv2/core.hpp>
#include <random>
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

// A tag of 9 px cells in a 220 x 200 image, tilted and in perspective,
// blurred, curved and sharpened (no code clipped).
const cv::Rect kCrop(20, 20, 170, 160);
std::array<double, kTagNumParams> TiltedTag() {
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
  return p;
}

// TiltedTag() through `encoding`.
void CheckJacobian(const LumaEncoding& encoding, int depth) {
  const TagBitmap bitmap = Tag36h11Bitmap(7);
  const cv::Mat luma = cv::Mat::zeros(200, 220, depth);
  const std::array<double, kTagNumParams> p = TiltedTag();
  TagImageCost cost(luma, bitmap, kCrop, encoding);
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

// The model is drawn only as far as the fitted pixels' filters reach: a
// pixel's level must not depend on how many pixels around it are fitted.
TEST(TagImageCost, APixelsLevelDoesNotDependOnWhichPixelsAreFitted) {
  const TagBitmap bitmap = Tag36h11Bitmap(7);
  const cv::Mat luma = cv::Mat::zeros(200, 220, CV_8U);
  const cv::Rect& crop = kCrop;
  const LumaEncoding encoding{.transfer = Transfer::kSdr, .full_range = false};
  std::array<double, kTagNumParams> p = TiltedTag();
  // The widest sharpening the fit allows, and a strong one, on a lighting
  // gradient that makes the table's level vary: the filters' reach is the
  // longest, and what they reach is not flat.
  p[kTagSharpenRadius] = kTagMaxSharpenRadiusPx;
  p[kTagSharpenAmount] = 1.5;
  p[kTagGainU] = 0.2;
  p[kTagGainV] = -0.1;
  // The near pixels end at the quiet zone's outer edge, whose halo then
  // lies outside them.
  const double near_cells = 0.0, far_cells = 1.5;
  TagImageCost near(luma, bitmap, crop, encoding);
  TagImageCost far(luma, bitmap, crop, encoding);
  std::array<double, kTagNumParams> start = p;
  near.Start(near_cells, start.data());
  far.Start(far_cells, start.data());
  ASSERT_GT(far.num_residuals(), near.num_residuals() + 1000);
  const std::vector<double> from_near = Residuals(near, p);
  const std::vector<double> from_far = Residuals(far, p);
  // Both walk the crop row by row; the near pixels are those within
  // near_cells of the quiet zone's edge (TagImageCost::Start).
  const Eigen::Matrix3d cell_from_pixel =
      TagPixelFromCell(bitmap, p.data()).inverse();
  const double n = bitmap.total_width;
  const auto within = [&](int u, int v, double cells) {
    const Eigen::Vector3d q =
        cell_from_pixel * Eigen::Vector3d(u + crop.x, v + crop.y, 1.0);
    const double x = q.x() / q.z(), y = q.y() / q.z();
    return x >= -cells && x <= n + cells && y >= -cells && y <= n + cells;
  };
  size_t i_near = 0, i_far = 0;
  double worst = 0.0;
  for (int v = 0; v < crop.height; ++v) {
    for (int u = 0; u < crop.width; ++u) {
      if (!within(u, v, far_cells)) continue;
      if (within(u, v, near_cells)) {
        ASSERT_LT(i_near, from_near.size());
        worst =
            std::max(worst, std::abs(from_near[i_near++] - from_far[i_far]));
      }
      ++i_far;
    }
  }
  EXPECT_EQ(i_near, from_near.size());
  EXPECT_EQ(i_far, from_far.size());
  EXPECT_LT(worst, 1e-9);
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

// The Jacobian is filtered by bands of rows, one per core, each reading the
// rows beyond it: any number of bands gives the whole image's numbers.
TEST(TagImageCost, JacobianIsTheSameOnAnyNumberOfCores) {
  const TagBitmap bitmap = Tag36h11Bitmap(7);
  const cv::Mat luma = cv::Mat::zeros(200, 220, CV_8U);
  const LumaEncoding encoding{.transfer = Transfer::kSdr, .full_range = false};
  const std::array<double, kTagNumParams> p = TiltedTag();
  const int threads = cv::getNumThreads();
  std::vector<std::vector<double>> jacobians_by_cores;
  for (const int cores : {1, 2}) {
    cv::setNumThreads(cores);
    TagImageCost cost(luma, bitmap, kCrop, encoding);
    std::array<double, kTagNumParams> start = p;
    cost.Start(0.5, start.data());
    std::vector<double> residuals(cost.num_residuals());
    std::vector<double> jacobian(residuals.size() * kTagNumParams);
    const double* blocks[1] = {p.data()};
    double* jacobians[1] = {jacobian.data()};
    ASSERT_TRUE(cost.Evaluate(blocks, residuals.data(), jacobians));
    jacobians_by_cores.push_back(jacobian);
  }
  cv::setNumThreads(threads);
  EXPECT_EQ(jacobians_by_cores[0], jacobians_by_cores[1]);
}

// Levenberg-Marquardt sees J and r only through |r + J d|^2 (and its
// gradient and curvature), which the square root form must keep for every
// step d, also where J^T J is singular.
void CheckSquareRootForm(int zero_column) {
  std::mt19937 random(7);
  std::normal_distribution<double> normal;
  const int n = 300;
  Eigen::MatrixXd j(n, kTagNumParams);
  Eigen::VectorXd r(n);
  for (int i = 0; i < n; ++i) {
    r[i] = normal(random);
    // Columns of very different sizes, as corners (px) against levels.
    for (int k = 0; k < kTagNumParams; ++k) {
      j(i, k) = normal(random) * std::pow(10.0, k % 5 - 2);
    }
  }
  if (zero_column >= 0) j.col(zero_column).setZero();
  NormalEquations equations;
  equations.squared_norm = r.squaredNorm();
  equations.jtj = j.transpose() * j;
  equations.jtr = j.transpose() * r;
  Eigen::Matrix<double, kTagNumParams + 1, 1> z;
  Eigen::Matrix<double, kTagNumParams + 1, kTagNumParams, Eigen::RowMajor> root;
  SquareRootForm(equations, z.data(), root.data());
  EXPECT_NEAR(z.squaredNorm(), r.squaredNorm(), 1e-10 * r.squaredNorm());
  EXPECT_TRUE(root.row(kTagNumParams).isZero());
  EXPECT_LT((root.transpose() * root - equations.jtj).norm(),
            1e-12 * equations.jtj.norm());
  EXPECT_LT((root.transpose() * z - equations.jtr).norm(),
            1e-10 * equations.jtr.norm());
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::Matrix<double, kTagNumParams, 1> d;
    for (int k = 0; k < kTagNumParams; ++k) {
      d[k] = normal(random) * std::pow(10.0, 2 - k % 5);
    }
    const double whole = (r + j * d).squaredNorm();
    EXPECT_NEAR((z + root * d).squaredNorm(), whole, 1e-9 * whole);
  }
}

TEST(SquareRootForm, KeepsEveryStepsCost) { CheckSquareRootForm(-1); }

TEST(SquareRootForm, KeepsEveryStepsCostWithAZeroColumn) {
  CheckSquareRootForm(kTagTable);
}

// The normal equations summed on all cores are those of the Jacobian Ceres
// would have been given.
TEST(TagImageCost, NormalEquationsAreThoseOfItsJacobian) {
  const TagBitmap bitmap = Tag36h11Bitmap(7);
  cv::Mat luma(200, 220, CV_8U);
  cv::randu(luma, 0, 255);
  const LumaEncoding encoding{.transfer = Transfer::kSdr, .full_range = false};
  const std::array<double, kTagNumParams> p = TiltedTag();
  TagImageCost cost(luma, bitmap, kCrop, encoding);
  std::array<double, kTagNumParams> start = p;
  cost.Start(0.5, start.data());
  const int n = cost.num_residuals();
  Eigen::VectorXd r(n);
  Eigen::Matrix<double, Eigen::Dynamic, kTagNumParams, Eigen::RowMajor> j(
      n, kTagNumParams);
  const double* blocks[1] = {p.data()};
  double* jacobians[1] = {j.data()};
  ASSERT_TRUE(cost.Evaluate(blocks, r.data(), jacobians));
  NormalEquations equations;
  cost.NormalEquationsAt(p.data(), &equations);
  EXPECT_NEAR(equations.squared_norm, r.squaredNorm(), 1e-12 * r.squaredNorm());
  EXPECT_NEAR(cost.SquaredNormAt(p.data()), r.squaredNorm(),
              1e-12 * r.squaredNorm());
  const NormalEquations::Matrix jtj = j.transpose() * j;
  const NormalEquations::Vector jtr = j.transpose() * r;
  EXPECT_LT((equations.jtj - jtj).norm(), 1e-12 * jtj.norm());
  EXPECT_LT((equations.jtr - jtr).norm(), 1e-12 * jtr.norm());
}

}  // namespace
}  // namespace softbench
