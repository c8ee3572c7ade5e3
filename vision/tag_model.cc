#include "vision/tag_model.h"

#include <ceres/ceres.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "util/check.h"
#include "vision/tag_image_model.h"

namespace softbench {

std::optional<std::string> TagModelOptions::Problem() const {
  if (!(margin_cells >= 0.5)) return "margin_cells must be >= 0.5";
  if (!(beyond_cells >= 0.0 && beyond_cells + 0.5 <= margin_cells)) {
    return "beyond_cells must be in [0, margin_cells - 0.5]";
  }
  if (max_iterations < 1) return "max_iterations must be >= 1";
  if (!(max_cell_px > 0.0)) return "max_cell_px must be > 0";
  return std::nullopt;
}

namespace {

// Levenberg-Marquardt on the normal equations, one thread (the cost's
// evaluations use both cores themselves).
ceres::Solver::Options SolverOptions(const TagModelOptions& options) {
  ceres::Solver::Options solver;
  // Eighteen parameters over some 15 000 pixels, handed to Ceres as their
  // normal equations' square root (TagImageNormalCost, 19 x 18). Their
  // squared condition is harmless here, where Ceres scales the columns and
  // Levenberg-Marquardt damps the diagonal: on FitTagModel's renders every
  // fitted scale, level and iteration count came out as with DENSE_QR of the
  // whole Jacobian.
  solver.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  solver.max_num_iterations = options.max_iterations;
  // Levenberg-Marquardt's first damping at a hundredth of the diagonal, not
  // Ceres's ten-thousandth (a Gauss-Newton step): from the start's guessed
  // processing, undamped steps overshoot along the valley where blur, pixel
  // filter and sharpening trade off, and were refused three or four times
  // in a row. On FitTagModel's eight renders the fits took 64 iterations
  // against 83, on the sharpened 720p clip 10 against 17, and every scale
  // moved by under 0.005 %, within the fit's own spread along that valley.
  solver.initial_trust_region_radius = 100.0;
  solver.num_threads = 1;
  // No projected line search at the bounds: it evaluates whole Jacobians,
  // and tripled the fit's cost wherever the fit settled on a bound (no lens
  // blur, the strongest curve); the trust region keeps its steps inside.
  solver.max_num_line_search_step_size_iterations = 0;
  // Steps under 1e-5 of the parameters' size (the corners' coordinates
  // dominate it: about 0.005 px a corner in a 720p frame) end the fit. On
  // footage without noise the cost falls toward nothing, and its relative
  // decrease (function_tolerance) never stops. Against 1e-6, the scale moved
  // under 0.002 % on FitTagModel's renders, in a third of the iterations
  // where they were most (31 against 12).
  solver.parameter_tolerance = 1e-5;
  return solver;
}

}  // namespace

TagModelFit FitTagModel(const cv::Mat& luma, const TagBitmap& bitmap,
                        const std::array<Eigen::Vector2d, 4>& corners,
                        const TagModelOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  TagModelFit fit;
  std::array<double, kTagNumParams> p{};
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
  const Eigen::Matrix3d pixel_from_cell = TagPixelFromCell(bitmap, p.data());
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
  auto pixels =
      std::make_unique<TagImageCost>(luma, bitmap, crop, options.luma_encoding);
  p[kTagBlur] = 0.5;
  p[kTagInk] = p[kTagTable] = 0.05;
  p[kTagPaper] = 0.8;
  pixels->Start(options.beyond_cells, p.data());
  p[kTagSharpenRadius] = 1.0;
  fit.pixels = pixels->num_residuals();
  ceres::Problem problem;
  problem.AddResidualBlock(new TagImageNormalCost(std::move(pixels)), nullptr,
                           p.data());  // owned by the problem
  const std::pair<TagImageParam, std::pair<double, double>> bounds[] = {
      {kTagBlur, {0.0, 3.0}},
      {kTagInk, {0.0, 1.0}},
      {kTagPaper, {0.0, 1.0}},
      {kTagTable, {0.0, 1.0}},
      {kTagToneCurve, {-0.5, 1.0}},
      {kTagSharpenRadius, {0.3, kTagMaxSharpenRadiusPx}},
      {kTagSharpenAmount, {0.0, 3.0}},
      {kTagPixelFilter, {0.0, 0.3}}};
  for (const auto& [index, range] : bounds) {
    problem.SetParameterLowerBound(p.data(), index, range.first);
    problem.SetParameterUpperBound(p.data(), index, range.second);
  }
  const ceres::Solver::Options solver = SolverOptions(options);
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  fit.iterations = static_cast<int>(summary.iterations.size());
  fit.rms_levels = std::sqrt(2.0 * summary.final_cost / fit.pixels);
  for (int i = 0; i < 4; ++i) fit.corners[i] = {p[2 * i], p[2 * i + 1]};
  fit.lens_blur_px = p[kTagBlur];
  fit.tone_curve = p[kTagToneCurve];
  fit.sharpen_radius_px = p[kTagSharpenRadius];
  fit.sharpen_amount = p[kTagSharpenAmount];
  fit.pixel_filter = p[kTagPixelFilter];
  if (summary.termination_type != ceres::CONVERGENCE) {
    fit.why_not = "the fit did not converge: " + summary.message;
    return fit;
  }
  fit.found = true;
  return fit;
}

}  // namespace softbench
