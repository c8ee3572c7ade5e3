#ifndef SOFTBENCH_VISION_TAG_IMAGE_MODEL_H_
#define SOFTBENCH_VISION_TAG_IMAGE_MODEL_H_

#include <ceres/cost_function.h>
#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

#include "vision/color_transfer.h"
#include "vision/tag_bitmap.h"

namespace softbench {

// The parameters of a tag's image (vision/tag_model.h), one block: the
// border's four outer corners (x, y) in libapriltag's order, the lens's blur
// (Gaussian sigma in light, px), the linear light of ink, paper and table,
// the lighting's gradient across the crop (per 100 px, right and down), the
// tone curve's strength, the sharpening's radius (px) and amount, and the
// side taps of a 3-tap filter on the pixels in light (a sensor's and a
// scaler's blur, which the pixel grid samples rather than a lens's
// continuous one).
enum TagImageParam {
  kTagCorners = 0,
  kTagBlur = 8,
  kTagInk,
  kTagPaper,
  kTagTable,
  kTagGainU,
  kTagGainV,
  kTagToneCurve,
  kTagSharpenRadius,
  kTagSharpenAmount,
  kTagPixelFilter,
  kTagNumParams
};
constexpr double kTagMaxSharpenRadiusPx = 3.0;

// The homography taking tag cells (column, row; the quiet zone's corner at
// 0) to pixels, through the border's outer corners (8 numbers, x then y) in
// libapriltag's order (counter-clockwise in the printed tag from its
// bottom-left).
Eigen::Matrix3d TagPixelFromCell(const TagBitmap& bitmap,
                                 const double* corners);

// What Levenberg-Marquardt needs of a least-squares problem at a point: the
// residuals' squared norm r·r, J^T J and J^T r.
struct NormalEquations {
  using Matrix = Eigen::Matrix<double, kTagNumParams, kTagNumParams>;
  using Vector = Eigen::Matrix<double, kTagNumParams, 1>;
  double squared_norm = 0.0;
  Matrix jtj = Matrix::Zero();
  Vector jtr = Vector::Zero();
};

// The same problem as kTagNumParams + 1 residuals: a square Jacobian R with
// R^T R = J^T J (from the pivoted LDL^T of J^T J, rows with no pivot left
// zero) and residuals z with R^T z = J^T r, then a last residual that makes
// up the norm, sqrt(r·r - z·z), whose Jacobian row is zero. For every step
// d, |z + R d|^2 + last^2 = |r + J d|^2, so Levenberg-Marquardt (its
// gradient, damping, Jacobi scaling and predicted decrease) takes the same
// steps on it. `residuals`: kTagNumParams + 1; `jacobian`: row-major, as
// many rows.
void SquareRootForm(const NormalEquations& equations, double* residuals,
                    double* jacobian);

// The tag's image over a crop of the luma, as a Ceres cost function of the
// parameters above: one residual per fitted pixel, the model's code less the
// luma's, in 8-bit levels. Its Jacobian is analytic: each pixel's cover of
// ink, paper and table is integrated in closed form, and so are its
// derivatives; the filters after it are linear, the curves pointwise.
//
// The model drawn at the last point evaluated is kept, with the derivatives
// of its light, so that the Jacobian at a point whose residuals were just
// evaluated (Levenberg-Marquardt's accepted step) does not draw it again,
// and so that its images are drawn over in place: one evaluation at a time
// (Ceres on one thread).
class TagImageCost : public ceres::CostFunction {
 public:
  // `luma`: CV_8UC1 or CV_16UC1 (vision/luma.h); `crop` lies inside it.
  // `bitmap` must outlive the cost.
  TagImageCost(const cv::Mat& luma, const TagBitmap& bitmap,
               const cv::Rect& crop, const LumaEncoding& encoding);
  ~TagImageCost() override;

  // Chooses the fitted pixels, those whose point on the tag (through the
  // corners in `params`) lies within `beyond_cells` of the quiet zone's
  // outer edge, either side; sets the residuals' count; and sets the
  // starting light of ink, paper and table in `params` (the medians of the
  // fitted pixels well inside cells of each, through the video's curve).
  void Start(double beyond_cells, double* params);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  // The residuals' squared norm at `params`.
  double SquaredNormAt(const double* params) const;
  // The normal equations at `params`, summed on all cores from the Jacobian
  // kept with the point drawn, so that Ceres need not copy and multiply a
  // Jacobian as big as the pixels on one core.
  void NormalEquationsAt(const double* params, NormalEquations* out) const;

 private:
  struct Light;
  struct Drawn;
  // The part of the crop the model is drawn on: where the filters of the
  // fitted pixels reach, at this sharpening radius; and each fitted pixel's
  // index in it.
  cv::Rect Region(double sharpen_radius_px, std::vector<int>* at) const;
  // The light over `region` (in the crop), with its derivatives, into
  // `light`.
  void DrawLight(const double* params, const cv::Rect& region,
                 Light* light) const;
  // The model drawn at `params`: the one kept when the parameters are the
  // same.
  Drawn& DrawnAt(const double* params) const;
  // The residuals at the point drawn, into `residuals` (one per fitted
  // pixel).
  void Residuals(const Drawn& drawn, double* residuals) const;
  // The Jacobian at the point drawn, row-major, a row per fitted pixel.
  void JacobianRows(const Drawn& drawn, double* jacobian) const;

  const TagBitmap& bitmap_;
  cv::Rect crop_;
  LumaEncoding encoding_;
  cv::Mat data_;             // CV_64F, 8-bit levels
  std::vector<int> fitted_;  // indices in the crop
  cv::Rect fitted_box_;      // their bounding box in the crop
  double black_level_ = 0, white_level_ = 255;
  mutable std::unique_ptr<Drawn> drawn_;  // the last point evaluated
};

// TagImageCost as Ceres fits it: SquareRootForm of its normal equations, so
// that the solver's work per step is on 19 x 18 numbers, not 15 000 x 18
// (docs/benchmarks.md, "The tag fitted whole: its cost"). Where only the
// cost is asked for, the residuals are the norm and zeros.
class TagImageNormalCost
    : public ceres::SizedCostFunction<kTagNumParams + 1, kTagNumParams> {
 public:
  explicit TagImageNormalCost(std::unique_ptr<TagImageCost> pixels);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  const TagImageCost& pixels() const { return *pixels_; }

 private:
  std::unique_ptr<TagImageCost> pixels_;
};

}  // namespace softbench

#endif  // SOFTBENCH_VISION_TAG_IMAGE_MODEL_H_
