#include "vision/tag_model.h"

#include <ceres/ceres.h>
#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "util/check.h"
#include "util/statistics.h"
#include "vision/luma.h"
#include "vision/tag_detector.h"

namespace softbench {
namespace {

// The parameters, one block: the four corners (x, y), the lens's blur, the
// linear light of ink, paper and table, the lighting's gradient across the
// crop (per 100 px, right and down), the tone curve's strength, the
// sharpening's radius and amount, and the side taps of a 3-tap filter on
// the pixels in light (a sensor's and a scaler's blur, which the pixel
// grid samples rather than a lens's continuous one).
enum Param {
  kCorners = 0,
  kBlur = 8,
  kInk,
  kPaper,
  kTable,
  kGainU,
  kGainV,
  kToneCurve,
  kSharpenRadius,
  kSharpenAmount,
  kPixelFilter,
  kNumParams
};
// The parameters that move the cells' cover: the corners and the blur.
constexpr int kGeometry = kBlur + 1;
constexpr double kMaxSharpenRadiusPx = 3.0;

// The homography taking tag cells (column, row; the quiet zone's corner at
// 0) to pixels, through the border's outer corners in libapriltag's order
// (counter-clockwise in the printed tag from its bottom-left).
Eigen::Matrix3d PixelFromCell(const TagBitmap& bitmap, const double* corners) {
  const double q = (bitmap.total_width - bitmap.width_at_border) / 2.0;
  const double e = q + bitmap.width_at_border;
  const std::optional<Eigen::Matrix3d> h =
      HomographyThrough({Eigen::Vector2d(q, e), Eigen::Vector2d(e, e),
                         Eigen::Vector2d(e, q), Eigen::Vector2d(q, q)},
                        {Eigen::Vector2d(corners[0], corners[1]),
                         Eigen::Vector2d(corners[2], corners[3]),
                         Eigen::Vector2d(corners[4], corners[5]),
                         Eigen::Vector2d(corners[6], corners[7])});
  // A fit's corners stay a quadrilateral near the start's.
  return h.value_or(Eigen::Matrix3d::Identity());
}

// The fraction of a pixel's footprint on the far side of a boundary at
// signed distance d [px] (positive: the pixel's centre beyond it): the
// footprint projected on the boundary's normal is a box of width w, blurred
// by a Gaussian of sigma s. F integrates the blurred step once.
double Coverage(double d, double w, double s) {
  const double reach = 0.5 * w + 7.0 * s;
  if (d >= reach) return 1.0;
  if (d <= -reach) return 0.0;
  const auto f = [s](double x) {
    const double z = x / s;
    return x * 0.5 * std::erfc(-z * std::numbers::sqrt2 / 2.0) +
           s * std::exp(-0.5 * z * z) / std::sqrt(2.0 * std::numbers::pi);
  };
  return (f(d + 0.5 * w) - f(d - 0.5 * w)) / w;
}

// Along one of the tag's axes at a pixel: the fraction of the pixel's
// footprint in each cell column (or row), from the point's cell coordinate
// `q`, its gradient in pixels and the blur.
struct AxisCover {
  std::vector<double> beyond;  // per boundary 0..n: coverage past it
  void Fill(double q, const Eigen::Vector2d& gradient, double blur, int n) {
    const double norm = gradient.norm();
    const double px_per_cell = 1.0 / norm;
    const double nx = std::abs(gradient.x()) / norm;
    const double ny = std::abs(gradient.y()) / norm;
    // A unit pixel projected on the normal: a box of the larger component,
    // convolved with one of the smaller, taken as its variance.
    const double w = std::max(nx, ny);
    const double minor = std::min(nx, ny);
    const double s = std::sqrt(blur * blur + minor * minor / 12.0 + 1e-8);
    // Boundaries more than Coverage's reach behind the point are passed
    // wholly, those as far ahead not at all.
    const double reach_cells = (0.5 * w + 7.0 * s) * norm;
    const int near_0 =
        std::clamp(static_cast<int>(std::floor(q - reach_cells)), 0, n + 1);
    const int near_1 = std::clamp(
        static_cast<int>(std::ceil(q + reach_cells)) + 1, near_0, n + 1);
    beyond.assign(n + 1, 0.0);
    std::fill(beyond.begin(), beyond.begin() + near_0, 1.0);
    for (int i = near_0; i < near_1; ++i) {
      beyond[i] = Coverage((q - i) * px_per_cell, w, s);
    }
  }
  // The cells [first, last) the footprint touches: past every boundary
  // before the first, past none after the last.
  std::pair<int, int> Cells() const {
    const int n = static_cast<int>(beyond.size()) - 1;
    int first = 0, last = n;
    while (first < n && beyond[first + 1] == 1.0) ++first;
    while (last > first && beyond[last - 1] == 0.0) --last;
    return {first, last};
  }
};

class TagImageModel {
 public:
  TagImageModel(const cv::Mat& luma, const TagBitmap& bitmap,
                const cv::Rect& crop, const TagModelOptions& options)
      : bitmap_(bitmap), crop_(crop), options_(options) {
    const double per_code = LevelsPerCode(luma.depth(), options.luma_encoding);
    black_level_ = BlackLevel(options.luma_encoding);
    white_level_ = options.luma_encoding.full_range ? 255.0 : 235.0;
    luma(crop).convertTo(data_, CV_64F, per_code);
    const int taps =
        2 * static_cast<int>(std::ceil(4 * kMaxSharpenRadiusPx)) + 1;
    kernel_size_ = cv::Size(taps, taps);
  }

  // Chooses the fitted pixels (those whose point on the tag lies within
  // options.beyond_cells of the quiet zone's outer edge, either side), and
  // sets the starting levels of ink, paper and table in light: the medians
  // of the fitted pixels well inside cells of each (0.3 cells from their
  // edges), through the video's curve.
  void Start(double* params) {
    const Eigen::Matrix3d cell_from_pixel =
        PixelFromCell(bitmap_, params).inverse();
    const int n = bitmap_.total_width;
    const double lo = -options_.beyond_cells;
    const double hi = n + options_.beyond_cells;
    std::vector<double> levels[3];  // ink, paper, table
    fitted_.clear();
    for (int v = 0; v < crop_.height; ++v) {
      for (int u = 0; u < crop_.width; ++u) {
        const Eigen::Vector3d q =
            cell_from_pixel * Eigen::Vector3d(u + crop_.x, v + crop_.y, 1.0);
        const double x = q.x() / q.z(), y = q.y() / q.z();
        if (!(x >= lo && x <= hi && y >= lo && y <= hi)) continue;
        fitted_.push_back(v * crop_.width + u);
        const double level = data_.at<double>(v, u);
        const bool inside = x > 0 && x < n && y > 0 && y < n;
        const double fx = x - std::floor(x), fy = y - std::floor(y);
        if (!inside && (x < -0.3 || x > n + 0.3 || y < -0.3 || y > n + 0.3)) {
          levels[2].push_back(level);
        } else if (inside && std::min({fx, fy, 1 - fx, 1 - fy}) > 0.3) {
          const bool white =
              bitmap_.IsWhite(static_cast<int>(y), static_cast<int>(x));
          levels[white ? 1 : 0].push_back(level);
        }
      }
    }
    const int where[3] = {kInk, kPaper, kTable};
    for (int k = 0; k < 3; ++k) {
      if (levels[k].empty()) continue;  // a table not in view: its start
      const double code =
          std::clamp((Median(std::move(levels[k])) - black_level_) /
                         (white_level_ - black_level_),
                     0.0, 1.0);
      params[where[k]] = ToLinear(options_.luma_encoding.transfer, code);
    }
  }
  int NumResiduals() const { return static_cast<int>(fitted_.size()); }

  // Each pixel's footprint, blurred by the lens, split into the fractions
  // on ink, paper and table (CV_64FC3): the geometry, which only the
  // corners and the blur move.
  cv::Mat Cover(const double* p) const {
    const Eigen::Matrix3d cell_from_pixel = PixelFromCell(bitmap_, p).inverse();
    const int n = bitmap_.total_width;
    cv::Mat cover(crop_.size(), CV_64FC3);
    cv::parallel_for_(cv::Range(0, crop_.height), [&](const cv::Range& rows) {
      AxisCover along_x, along_y;
      for (int v = rows.start; v < rows.end; ++v) {
        cv::Vec3d* out = cover.ptr<cv::Vec3d>(v);
        for (int u = 0; u < crop_.width; ++u) {
          const Eigen::Vector3d h =
              cell_from_pixel * Eigen::Vector3d(u + crop_.x, v + crop_.y, 1.0);
          const double x = h.x() / h.z(), y = h.y() / h.z();
          // d(x, y)/d(pixel) of the projective map.
          const Eigen::Vector2d gx =
              (cell_from_pixel.block<1, 2>(0, 0).transpose() -
               x * cell_from_pixel.block<1, 2>(2, 0).transpose()) /
              h.z();
          const Eigen::Vector2d gy =
              (cell_from_pixel.block<1, 2>(1, 0).transpose() -
               y * cell_from_pixel.block<1, 2>(2, 0).transpose()) /
              h.z();
          along_x.Fill(x, gx, p[kBlur], n);
          along_y.Fill(y, gy, p[kBlur], n);
          const double in_x = along_x.beyond[0] - along_x.beyond[n];
          const double in_y = along_y.beyond[0] - along_y.beyond[n];
          cv::Vec3d fractions(0.0, 0.0, 1.0 - in_x * in_y);
          const auto [row_0, row_1] = along_y.Cells();
          const auto [col_0, col_1] = along_x.Cells();
          for (int row = row_0; row < row_1; ++row) {
            const double cover_y =
                along_y.beyond[row] - along_y.beyond[row + 1];
            if (cover_y == 0.0) continue;
            for (int col = col_0; col < col_1; ++col) {
              const double cover_x =
                  along_x.beyond[col] - along_x.beyond[col + 1];
              if (cover_x == 0.0) continue;
              fractions[bitmap_.IsWhite(row, col) ? 1 : 0] += cover_x * cover_y;
            }
          }
          out[u] = fractions;
        }
      }
    });
    return cover;
  }

  // The codes the model predicts over the crop, in 8-bit levels.
  cv::Mat Predict(const double* p) const {
    const Eigen::Matrix<double, kGeometry, 1> geometry =
        Eigen::Map<const Eigen::Matrix<double, kGeometry, 1>>(p);
    // Forward differences move one parameter at a time: for the levels and
    // the processing (half of them) the cells' cover is the last one's.
    if (cover_.empty() || geometry != cover_geometry_) {
      cover_ = Cover(p);
      cover_geometry_ = geometry;
    }
    const double cx = crop_.x + 0.5 * crop_.width;
    const double cy = crop_.y + 0.5 * crop_.height;
    cv::Mat codes(crop_.size(), CV_64F);
    for (int v = 0; v < crop_.height; ++v) {
      const cv::Vec3d* cover = cover_.ptr<cv::Vec3d>(v);
      double* out = codes.ptr<double>(v);
      for (int u = 0; u < crop_.width; ++u) {
        const double light = cover[u][0] * p[kInk] + cover[u][1] * p[kPaper] +
                             cover[u][2] * p[kTable];
        out[u] = light * (1.0 + 0.01 * (p[kGainU] * (u + crop_.x - cx) +
                                        p[kGainV] * (v + crop_.y - cy)));
      }
    }
    const double w = p[kPixelFilter];
    const cv::Mat taps = (cv::Mat_<double>(3, 1) << w, 1.0 - 2.0 * w, w);
    cv::sepFilter2D(codes, codes, CV_64F, taps, taps, cv::Point(-1, -1), 0.0,
                    cv::BORDER_REPLICATE);
    codes.forEach<double>([&](double& value, const int*) {
      double c = FromLinear(options_.luma_encoding.transfer,
                            std::clamp(value, 0.0, 1.0));
      c = std::clamp(c, 0.0, 1.0);
      value =
          (1.0 - p[kToneCurve]) * c + p[kToneCurve] * c * c * (3.0 - 2.0 * c);
    });
    cv::Mat soft;
    cv::GaussianBlur(codes, soft, kernel_size_, p[kSharpenRadius],
                     p[kSharpenRadius], cv::BORDER_REPLICATE);
    // The camera's codes clip at black and white (its R'G'B' do, before
    // they become luma), which hides the halos of ink and paper.
    cv::Mat levels = codes + p[kSharpenAmount] * (codes - soft);
    cv::min(cv::max(levels, 0.0), 1.0, levels);
    return black_level_ + (white_level_ - black_level_) * levels;
  }

  bool operator()(double const* const* params, double* residuals) const {
    const cv::Mat levels = Predict(params[0]);
    const double* model = levels.ptr<double>();
    const double* data = data_.ptr<double>();
    for (size_t i = 0; i < fitted_.size(); ++i) {
      residuals[i] = model[fitted_[i]] - data[fitted_[i]];
    }
    return true;
  }

 private:
  const TagBitmap& bitmap_;
  cv::Rect crop_;
  TagModelOptions options_;
  cv::Mat data_;  // CV_64F, 8-bit levels
  std::vector<int> fitted_;
  double black_level_ = 0, white_level_ = 255;
  cv::Size kernel_size_;
  // The last Cover() and the corners and blur it was for. Ceres evaluates
  // this one cost function from one thread (num_threads = 1).
  mutable cv::Mat cover_;
  mutable Eigen::Matrix<double, kGeometry, 1> cover_geometry_;
};

}  // namespace

std::optional<std::string> TagModelOptions::Problem() const {
  if (!(margin_cells >= 0.5)) return "margin_cells must be >= 0.5";
  if (!(beyond_cells >= 0.0 && beyond_cells + 0.5 <= margin_cells)) {
    return "beyond_cells must be in [0, margin_cells - 0.5]";
  }
  if (max_iterations < 1) return "max_iterations must be >= 1";
  if (!(max_cell_px > 0.0)) return "max_cell_px must be > 0";
  return std::nullopt;
}

TagModelFit FitTagModel(const cv::Mat& luma, const TagBitmap& bitmap,
                        const std::array<Eigen::Vector2d, 4>& corners,
                        const TagModelOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  TagModelFit fit;
  std::array<double, kNumParams> p{};
  for (int i = 0; i < 4; ++i) {
    p[2 * i] = corners[i].x();
    p[2 * i + 1] = corners[i].y();
  }
  double side_px = 0.0;
  for (int i = 0; i < 4; ++i)
    side_px += (corners[(i + 1) % 4] - corners[i]).norm() / 4;
  const double cell_px = side_px / bitmap.width_at_border;
  if (cell_px > options.max_cell_px) {
    fit.why_not = fmt::format("cells of {:.1f} px, more than {:.0f}", cell_px,
                              options.max_cell_px);
    return fit;
  }
  // The crop: the tag with its quiet zone and margin_cells of table.
  const Eigen::Matrix3d pixel_from_cell = PixelFromCell(bitmap, p.data());
  const double far = bitmap.total_width + options.margin_cells;
  double lo_u = INFINITY, lo_v = INFINITY, hi_u = -INFINITY, hi_v = -INFINITY;
  for (const double x : {-options.margin_cells, far}) {
    for (const double y : {-options.margin_cells, far}) {
      const Eigen::Vector3d h = pixel_from_cell * Eigen::Vector3d(x, y, 1.0);
      lo_u = std::min(lo_u, h.x() / h.z());
      hi_u = std::max(hi_u, h.x() / h.z());
      lo_v = std::min(lo_v, h.y() / h.z());
      hi_v = std::max(hi_v, h.y() / h.z());
    }
  }
  const cv::Rect crop(cv::Point(static_cast<int>(std::floor(lo_u)),
                                static_cast<int>(std::floor(lo_v))),
                      cv::Point(static_cast<int>(std::ceil(hi_u)) + 1,
                                static_cast<int>(std::ceil(hi_v)) + 1));
  if ((crop & cv::Rect(0, 0, luma.cols, luma.rows)) != crop) {
    fit.why_not = "the tag and its margin leave the image";
    return fit;
  }
  auto* model = new TagImageModel(luma, bitmap, crop, options);
  p[kBlur] = 0.5;
  p[kInk] = p[kTable] = 0.05;
  p[kPaper] = 0.8;
  model->Start(p.data());
  p[kSharpenRadius] = 1.0;
  auto* cost =
      new ceres::DynamicNumericDiffCostFunction<TagImageModel, ceres::FORWARD>(
          model);
  cost->AddParameterBlock(kNumParams);
  cost->SetNumResiduals(model->NumResiduals());
  ceres::Problem problem;
  problem.AddResidualBlock(cost, nullptr, p.data());
  const std::pair<Param, std::pair<double, double>> bounds[] = {
      {kBlur, {0.0, 3.0}},
      {kInk, {0.0, 1.0}},
      {kPaper, {0.0, 1.0}},
      {kTable, {0.0, 1.0}},
      {kToneCurve, {-0.5, 1.0}},
      {kSharpenRadius, {0.3, kMaxSharpenRadiusPx}},
      {kSharpenAmount, {0.0, 3.0}},
      {kPixelFilter, {0.0, 0.3}}};
  for (const auto& [index, range] : bounds) {
    problem.SetParameterLowerBound(p.data(), index, range.first);
    problem.SetParameterUpperBound(p.data(), index, range.second);
  }
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = options.max_iterations;
  solver.num_threads = 1;
  // No projected line search at the bounds: it evaluates whole Jacobians,
  // and tripled the fit's cost wherever the fit settled on a bound (no lens
  // blur, the strongest curve); the trust region keeps its steps inside.
  solver.max_num_line_search_step_size_iterations = 0;
  // Steps under a millionth of the parameters' size (about 3e-4 px on the
  // corners) end the fit: on footage without noise the cost falls toward
  // nothing, and its relative decrease (function_tolerance) never stops.
  solver.parameter_tolerance = 1e-6;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  fit.iterations = static_cast<int>(summary.iterations.size());
  fit.pixels = model->NumResiduals();
  fit.rms_levels = std::sqrt(2.0 * summary.final_cost / fit.pixels);
  for (int i = 0; i < 4; ++i) fit.corners[i] = {p[2 * i], p[2 * i + 1]};
  fit.lens_blur_px = p[kBlur];
  fit.tone_curve = p[kToneCurve];
  fit.sharpen_radius_px = p[kSharpenRadius];
  fit.sharpen_amount = p[kSharpenAmount];
  fit.pixel_filter = p[kPixelFilter];
  if (summary.termination_type != ceres::CONVERGENCE) {
    fit.why_not = "the fit did not converge: " + summary.message;
    return fit;
  }
  fit.found = true;
  return fit;
}

}  // namespace softbench
