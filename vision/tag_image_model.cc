#include "vision/tag_image_model.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <tuple>

#include "util/statistics.h"
#include "vision/luma.h"
#include "vision/tag_detector.h"

namespace softbench {
namespace {

// The parameters that move the light before the pixel filter: the corners,
// the blur, the levels and the lighting's gradient.
constexpr int kLightParams = kTagToneCurve;

// The fraction of a pixel's footprint on the far side of a boundary at
// signed distance d [px] (positive: the pixel's centre beyond it), and its
// derivatives: the footprint projected on the boundary's normal is a box of
// width w, blurred by a Gaussian of sigma s. With Phi and phi the normal
// distribution and density, F(x) = x Phi(x/s) + s phi(x/s) integrates the
// blurred step once; dF/dx = Phi(x/s) and dF/ds = phi(x/s).
struct Coverage {
  double value = 0.0, d_d = 0.0, d_w = 0.0, d_s = 0.0;
  Coverage(double d, double w, double s) {
    const double reach = 0.5 * w + 7.0 * s;
    if (d >= reach) value = 1.0;
    if (d >= reach || d <= -reach) return;
    const double x[2] = {d + 0.5 * w, d - 0.5 * w};
    double cdf[2], pdf[2], f[2];
    for (int k = 0; k < 2; ++k) {
      const double z = x[k] / s;
      cdf[k] = 0.5 * std::erfc(-z * std::numbers::sqrt2 / 2.0);
      pdf[k] = std::exp(-0.5 * z * z) / std::sqrt(2.0 * std::numbers::pi);
      f[k] = x[k] * cdf[k] + s * pdf[k];
    }
    value = (f[0] - f[1]) / w;
    d_d = (cdf[0] - cdf[1]) / w;
    d_s = (pdf[0] - pdf[1]) / w;
    d_w = (0.5 * (cdf[0] + cdf[1]) - value) / w;
  }
};

// A pixel's footprint projected on the normal of one of the tag's axes,
// from the axis's gradient in pixels `g` and the lens's blur: a box of
// width w (the larger component of the unit pixel), convolved with one of
// the smaller (taken as its variance) and the blur, as a Gaussian of sigma
// s; and how far from the footprint's centre a boundary still moves its
// cover [cells].
struct Footprint {
  double norm, w, minor, s, reach_cells;
  int major;
  Footprint(const Eigen::Vector2d& g, double blur)
      : norm(g.norm()), major(std::abs(g.x()) >= std::abs(g.y()) ? 0 : 1) {
    w = std::abs(g[major]) / norm;
    minor = std::abs(g[1 - major]) / norm;
    s = std::sqrt(blur * blur + minor * minor / 12.0 + 1e-8);
    reach_cells = (0.5 * w + 7.0 * s) * norm;
  }
  // Whether the boundaries either side of cell coordinate `q` are both out
  // of reach (Coverage is then exactly 0 or 1 for every boundary).
  bool InOneCell(double q) const {
    const double f = q - std::floor(q);
    return f >= reach_cells && 1.0 - f >= reach_cells;
  }
};

// Along one of the tag's axes at a pixel: the fraction of the pixel's
// footprint past each cell boundary, from the point's cell coordinate `q`,
// its gradient in pixels `g`, its footprint and the blur; and the
// derivatives of each by (q, gradient x, gradient y, blur). Only the
// boundaries within the blur's reach are evaluated and stored: those before
// are passed wholly, those after not at all.
class AxisCover {
 public:
  void Fill(double q, const Eigen::Vector2d& g, const Footprint& f, double blur,
            int n) {
    n_ = n;
    const double px_per_cell = 1.0 / f.norm;
    near_0_ =
        std::clamp(static_cast<int>(std::floor(q - f.reach_cells)), 0, n + 1);
    near_1_ = std::clamp(static_cast<int>(std::ceil(q + f.reach_cells)) + 1,
                         near_0_, n + 1);
    if (beyond_.size() < static_cast<size_t>(n) + 1) {
      beyond_.resize(n + 1);
      d_beyond_.resize(n + 1);
    }
    const double norm = f.norm;
    // d(|g_j| / |g|) / dg.
    const auto d_ratio = [&](int j) {
      Eigen::Vector2d r = -std::abs(g[j]) / (norm * norm * norm) * g;
      r[j] += (g[j] >= 0.0 ? 1.0 : -1.0) / norm;
      return r;
    };
    Eigen::Vector2d d_w = Eigen::Vector2d::Zero();
    Eigen::Vector2d d_s_d_g = Eigen::Vector2d::Zero();
    if (near_1_ > near_0_) {
      d_w = d_ratio(f.major);
      d_s_d_g = f.minor / (12.0 * f.s) * d_ratio(1 - f.major);
    }
    for (int i = near_0_; i < near_1_; ++i) {
      const Coverage c((q - i) * px_per_cell, f.w, f.s);
      beyond_[i] = c.value;
      const Eigen::Vector2d d_g =
          c.d_d * (-(q - i) / (norm * norm * norm)) * g + c.d_w * d_w +
          c.d_s * d_s_d_g;
      d_beyond_[i] << c.d_d * px_per_cell, d_g.x(), d_g.y(), c.d_s * blur / f.s;
    }
  }
  double Beyond(int i) const {
    return i < near_0_ ? 1.0 : i >= near_1_ ? 0.0 : beyond_[i];
  }
  Eigen::Vector4d DBeyond(int i) const {
    return i < near_0_ || i >= near_1_ ? Eigen::Vector4d::Zero() : d_beyond_[i];
  }
  // Whether any boundary is within reach: where none is, the footprint's
  // cover does not move with the point, and its derivatives are zero.
  bool Moves() const { return near_1_ > near_0_; }
  // The cells [first, last) the footprint touches: past every boundary
  // before the first, past none after the last (only the boundaries in
  // reach are searched).
  std::pair<int, int> Cells() const {
    int first = std::clamp(near_0_ - 1, 0, n_);
    while (first < n_ && Beyond(first + 1) == 1.0) ++first;
    int last = std::clamp(near_1_, first, n_);
    while (last > first && Beyond(last - 1) == 0.0) --last;
    return {first, last};
  }

 private:
  int n_ = 0, near_0_ = 0, near_1_ = 0;
  std::vector<double> beyond_;
  std::vector<Eigen::Vector4d> d_beyond_;
};

// A pixel's point on the tag and its gradient along each axis.
struct PixelOnTag {
  Eigen::Vector3d pixel, h;
  double x, y;
  Eigen::Vector2d gx, gy;
  PixelOnTag(const Eigen::Matrix3d& cell_from_pixel, double u, double v)
      : pixel(u, v, 1.0),
        h(cell_from_pixel * pixel),
        x(h.x() / h.z()),
        y(h.y() / h.z()) {
    const Eigen::Vector2d c = cell_from_pixel.block<1, 2>(2, 0).transpose();
    gx = (cell_from_pixel.block<1, 2>(0, 0).transpose() - x * c) / h.z();
    gy = (cell_from_pixel.block<1, 2>(1, 0).transpose() - y * c) / h.z();
  }
  // d f / d cell_from_pixel, for f with derivatives `d_x` by (x, gx) and
  // `d_y` by (y, gy): so that a change D of cell_from_pixel changes f by the
  // sum of this matrix times D, entry by entry. From h = M p, x = h0 / h2,
  // gx = (M0' - x M2') / h2 (M_r' the first two entries of row r), and the
  // same for y.
  Eigen::Matrix3d Derivative(const Eigen::Matrix3d& cell_from_pixel,
                             const Eigen::Vector3d& d_x,
                             const Eigen::Vector3d& d_y) const {
    const Eigen::Vector2d m2 = cell_from_pixel.block<1, 2>(2, 0).transpose();
    const Eigen::Vector2d bx = d_x.tail<2>(), by = d_y.tail<2>();
    // By x and y with the gradients' own dependence on them folded in.
    const double alpha = d_x[0] - bx.dot(m2) / h.z();
    const double beta = d_y[0] - by.dot(m2) / h.z();
    const double delta = -(alpha * x + beta * y) - (bx.dot(gx) + by.dot(gy));
    Eigen::Matrix3d a;
    a.row(0) = alpha * pixel.transpose();
    a.row(1) = beta * pixel.transpose();
    a.row(2) = delta * pixel.transpose();
    a.block<1, 2>(0, 0) += bx.transpose();
    a.block<1, 2>(1, 0) += by.transpose();
    a.block<1, 2>(2, 0) -= (x * bx + y * by).transpose();
    return a / h.z();
  }
};

// A separable filter, edges replicated, into `out` (allocated only when its
// size differs).
void Separable(const cv::Mat& image, const cv::Mat& kx, const cv::Mat& ky,
               cv::Mat* out) {
  cv::sepFilter2D(image, *out, CV_64F, kx, ky, cv::Point(-1, -1), 0.0,
                  cv::BORDER_REPLICATE);
}

// Runs fn(rows) on as many bands of [0, rows) as there are cores, a band on
// each: a filter of an image's band (a cv::Mat ROI) reads the rows beyond
// it, so each band's numbers are the whole image's.
template <typename Fn>
void ForEachBand(int rows, const Fn& fn) {
  const int bands = std::max(1, cv::getNumThreads());
  cv::parallel_for_(
      cv::Range(0, bands),
      [&](const cv::Range& range) {
        for (int b = range.start; b < range.end; ++b) {
          fn(cv::Range(rows * b / bands, rows * (b + 1) / bands));
        }
      },
      bands);
}

// The sharpening's Gaussian of sigma `r`, normalised, to 4 sigma each side
// (cv::getGaussianKernel, with the size cv::GaussianBlur gives a
// floating-point image; the taps beyond hold 6e-5 of its weight, and
// taking 4 sigma of the widest radius instead, 25 taps, nearly doubled the
// filters' work at 1.5 px), and its derivative by r at that size:
// g_t (t^2 - sum g t^2) / r^3 for the normalised taps.
int SharpenHalfTaps(double r) { return static_cast<int>(std::ceil(4.0 * r)); }

std::pair<cv::Mat, cv::Mat> GaussianAndDerivative(double r) {
  const int half_taps = SharpenHalfTaps(r);
  const cv::Mat g = cv::getGaussianKernel(2 * half_taps + 1, r, CV_64F);
  cv::Mat t2(g.size(), CV_64F);
  for (int i = 0; i < g.rows; ++i) {
    t2.at<double>(i) = (i - half_taps) * (i - half_taps);
  }
  const double moment = g.dot(t2);
  return {g, g.mul(t2 - moment) / (r * r * r)};
}

}  // namespace

Eigen::Matrix3d TagPixelFromCell(const TagBitmap& bitmap,
                                 const double* corners) {
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

namespace {

// The light at (v, u) of a pixel `on` whose footprint lies in one cell
// (Footprint::InOneCell along both axes), or wholly on the table: its
// level's, lit; and its derivatives, by that level and the gradient only
// (neither the corners nor the blur move it).
void FlatPixel(const PixelOnTag& on, int n, const double levels[3],
               const TagBitmap& bitmap, double gain, double du, double dv,
               int v, int u, cv::Mat* light,
               std::array<cv::Mat, kLightParams>* d_light) {
  const int col = static_cast<int>(std::floor(on.x));
  const int row = static_cast<int>(std::floor(on.y));
  const int colour = col >= 0 && col < n && row >= 0 && row < n
                         ? (bitmap.IsWhite(row, col) ? 1 : 0)
                         : 2;  // ink, paper, table
  light->at<double>(v, u) = levels[colour] * gain;
  for (int k = 0; k <= kTagBlur; ++k) (*d_light)[k].at<double>(v, u) = 0.0;
  for (int m = 0; m < 3; ++m) {
    (*d_light)[kTagInk + m].at<double>(v, u) = m == colour ? gain : 0.0;
  }
  (*d_light)[kTagGainU].at<double>(v, u) = levels[colour] * du;
  (*d_light)[kTagGainV].at<double>(v, u) = levels[colour] * dv;
}

}  // namespace

struct TagImageCost::Light {
  cv::Mat light;  // CV_64F, before the pixel filter
  // d light / d parameter, for the parameters before kLightParams.
  std::array<cv::Mat, kLightParams> d_light;
};

TagImageCost::TagImageCost(const cv::Mat& luma, const TagBitmap& bitmap,
                           const cv::Rect& crop, const LumaEncoding& encoding)
    : bitmap_(bitmap), crop_(crop), encoding_(encoding) {
  const double per_code = LevelsPerCode(luma.depth(), encoding);
  black_level_ = BlackLevel(encoding);
  white_level_ = encoding.full_range ? 255.0 : 235.0;
  luma(crop).convertTo(data_, CV_64F, per_code);
  mutable_parameter_block_sizes()->push_back(kTagNumParams);
}

void TagImageCost::Start(double beyond_cells, double* params) {
  const Eigen::Matrix3d cell_from_pixel =
      TagPixelFromCell(bitmap_, params).inverse();
  const int n = bitmap_.total_width;
  const double lo = -beyond_cells;
  const double hi = n + beyond_cells;
  std::vector<double> levels[3];  // ink, paper, table
  fitted_.clear();
  int u_0 = crop_.width, v_0 = crop_.height, u_1 = 0, v_1 = 0;
  for (int v = 0; v < crop_.height; ++v) {
    for (int u = 0; u < crop_.width; ++u) {
      const Eigen::Vector3d q =
          cell_from_pixel * Eigen::Vector3d(u + crop_.x, v + crop_.y, 1.0);
      const double x = q.x() / q.z(), y = q.y() / q.z();
      if (!(x >= lo && x <= hi && y >= lo && y <= hi)) continue;
      fitted_.push_back(v * crop_.width + u);
      u_0 = std::min(u_0, u);
      v_0 = std::min(v_0, v);
      u_1 = std::max(u_1, u + 1);
      v_1 = std::max(v_1, v + 1);
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
  const int where[3] = {kTagInk, kTagPaper, kTagTable};
  for (int k = 0; k < 3; ++k) {
    if (levels[k].empty()) continue;  // a table not in view: its start
    const double code =
        std::clamp((Median(std::move(levels[k])) - black_level_) /
                       (white_level_ - black_level_),
                   0.0, 1.0);
    params[where[k]] = ToLinear(encoding_.transfer, code);
  }
  fitted_box_ = cv::Rect(cv::Point(u_0, v_0), cv::Point(u_1, v_1));
  set_num_residuals(static_cast<int>(fitted_.size()));
}

// Each pixel's footprint, blurred by the lens, split into the fractions on
// ink, paper and table, lit by the levels and the gradient; and the
// derivatives of that light by the corners, the blur, the levels and the
// gradient.
void TagImageCost::DrawLight(const double* p, const cv::Rect& region,
                             Light* out) const {
  const Eigen::Matrix3d cell_from_pixel =
      TagPixelFromCell(bitmap_, p).inverse();
  // d cell_from_pixel / d corner, by central differences of the 8x8 solve
  // (smooth in the corners; 1e-4 px leaves 1e-10 of truncation).
  std::array<Eigen::Matrix3d, 8> d_cell_from_pixel;
  for (int k = 0; k < 8; ++k) {
    std::array<double, 8> corners;
    std::copy(p, p + 8, corners.begin());
    const double step = 1e-4;
    corners[k] = p[k] + step;
    const Eigen::Matrix3d plus = TagPixelFromCell(bitmap_, corners.data());
    corners[k] = p[k] - step;
    const Eigen::Matrix3d minus = TagPixelFromCell(bitmap_, corners.data());
    d_cell_from_pixel[k] =
        -cell_from_pixel * ((plus - minus) / (2 * step)) * cell_from_pixel;
  }
  out->light.create(region.size(), CV_64F);
  for (cv::Mat& d : out->d_light) d.create(region.size(), CV_64F);
  const int n = bitmap_.total_width;
  const double cx = crop_.x + 0.5 * crop_.width;
  const double cy = crop_.y + 0.5 * crop_.height;
  const double levels[3] = {p[kTagInk], p[kTagPaper], p[kTagTable]};
  cv::parallel_for_(cv::Range(0, region.height), [&](const cv::Range& rows) {
    AxisCover along_x, along_y;
    for (int v = rows.start; v < rows.end; ++v) {
      for (int u = 0; u < region.width; ++u) {
        const PixelOnTag on(cell_from_pixel, u + crop_.x + region.x,
                            v + crop_.y + region.y);
        const double du = 0.01 * (on.pixel.x() - cx);
        const double dv = 0.01 * (on.pixel.y() - cy);
        const double gain = 1.0 + p[kTagGainU] * du + p[kTagGainV] * dv;
        // Most pixels lie inside one cell, beyond the blur's reach of its
        // boundaries: their light is drawn without evaluating any cover
        // (BM_FitTagModel 46.6 -> 37.5 ms), to the same numbers.
        const Footprint foot_x(on.gx, p[kTagBlur]), foot_y(on.gy, p[kTagBlur]);
        if (foot_x.InOneCell(on.x) && foot_y.InOneCell(on.y)) {
          FlatPixel(on, n, levels, bitmap_, gain, du, dv, v, u, &out->light,
                    &out->d_light);
          continue;
        }
        along_x.Fill(on.x, on.gx, foot_x, p[kTagBlur], n);
        along_y.Fill(on.y, on.gy, foot_y, p[kTagBlur], n);
        const double in_x = along_x.Beyond(0) - along_x.Beyond(n);
        const double in_y = along_y.Beyond(0) - along_y.Beyond(n);
        double fractions[3] = {0.0, 0.0, 1.0 - in_x * in_y};
        // d(fractions · levels) / d(x axis's q, g, blur) and the y axis's.
        Eigen::Vector4d d_x =
            -levels[2] * in_y * (along_x.DBeyond(0) - along_x.DBeyond(n));
        Eigen::Vector4d d_y =
            -levels[2] * in_x * (along_y.DBeyond(0) - along_y.DBeyond(n));
        const auto [row_0, row_1] = along_y.Cells();
        const auto [col_0, col_1] = along_x.Cells();
        for (int row = row_0; row < row_1; ++row) {
          const double cover_y = along_y.Beyond(row) - along_y.Beyond(row + 1);
          if (cover_y == 0.0) continue;
          for (int col = col_0; col < col_1; ++col) {
            const double cover_x =
                along_x.Beyond(col) - along_x.Beyond(col + 1);
            if (cover_x == 0.0) continue;
            const int colour = bitmap_.IsWhite(row, col) ? 1 : 0;
            fractions[colour] += cover_x * cover_y;
            d_x += levels[colour] * cover_y *
                   (along_x.DBeyond(col) - along_x.DBeyond(col + 1));
            d_y += levels[colour] * cover_x *
                   (along_y.DBeyond(row) - along_y.DBeyond(row + 1));
          }
        }
        const double lit = fractions[0] * levels[0] + fractions[1] * levels[1] +
                           fractions[2] * levels[2];
        out->light.at<double>(v, u) = lit * gain;
        const bool moves = along_x.Moves() || along_y.Moves();
        const Eigen::Matrix3d d_by_matrix =
            moves ? Eigen::Matrix3d(gain * on.Derivative(cell_from_pixel,
                                                         d_x.head<3>(),
                                                         d_y.head<3>()))
                  : Eigen::Matrix3d::Zero();
        for (int k = 0; k < 8; ++k) {
          out->d_light[k].at<double>(v, u) =
              d_by_matrix.cwiseProduct(d_cell_from_pixel[k]).sum();
        }
        out->d_light[kTagBlur].at<double>(v, u) = gain * (d_x[3] + d_y[3]);
        out->d_light[kTagInk].at<double>(v, u) = gain * fractions[0];
        out->d_light[kTagPaper].at<double>(v, u) = gain * fractions[1];
        out->d_light[kTagTable].at<double>(v, u) = gain * fractions[2];
        out->d_light[kTagGainU].at<double>(v, u) = lit * du;
        out->d_light[kTagGainV].at<double>(v, u) = lit * dv;
      }
    }
  });
}

cv::Rect TagImageCost::Region(double sharpen_radius_px,
                              std::vector<int>* at) const {
  // The pixel filter's tap and the sharpening's.
  const int reach = SharpenHalfTaps(sharpen_radius_px) + 1;
  const cv::Rect region =
      cv::Rect(fitted_box_.x - reach, fitted_box_.y - reach,
               fitted_box_.width + 2 * reach, fitted_box_.height + 2 * reach) &
      cv::Rect(cv::Point(0, 0), crop_.size());
  at->resize(fitted_.size());
  for (size_t i = 0; i < fitted_.size(); ++i) {
    (*at)[i] = (fitted_[i] / crop_.width - region.y) * region.width +
               fitted_[i] % crop_.width - region.x;
  }
  return region;
}

// The model at one point: the light with its derivatives, the codes with
// their slopes, and the codes sharpened. Its images are drawn over again in
// place at the next point (cv::Mat::create keeps an image of the same size).
struct TagImageCost::Drawn {
  std::array<double, kTagNumParams> params;
  cv::Rect region;
  std::vector<int> at;  // each fitted pixel's index in the region
  // The pixel filter's taps, the sharpening's Gaussian and its derivative by
  // the radius.
  cv::Mat taps, gaussian, d_gaussian;
  Light light;
  cv::Mat filtered, codes, slope, by_strength, soft, sharpened;
  // NormalEquationsAt's residuals and Jacobian, kept for the next point.
  std::vector<double> residuals, jacobian;
};

TagImageCost::~TagImageCost() = default;

TagImageCost::Drawn& TagImageCost::DrawnAt(const double* p) const {
  if (drawn_ && std::equal(p, p + kTagNumParams, drawn_->params.begin())) {
    return *drawn_;
  }
  if (!drawn_) drawn_ = std::make_unique<Drawn>();
  Drawn& d = *drawn_;
  std::copy(p, p + kTagNumParams, d.params.begin());
  d.region = Region(p[kTagSharpenRadius], &d.at);
  // With the derivatives even for the residuals alone: most points whose
  // residuals are evaluated are Levenberg-Marquardt's accepted steps, whose
  // Jacobian is asked for next and then costs only its columns' filters.
  DrawLight(p, d.region, &d.light);
  // The pixel filter, in light: taps (w, 1 - 2w, w) both ways; then the
  // video's curve (clipped at black and white) and the tone curve: the
  // codes, with their slope by the filtered light and by the curve's
  // strength. Pointwise after the filter, so a band of rows on each core.
  const double w = p[kTagPixelFilter];
  d.taps = (cv::Mat_<double>(3, 1) << w, 1.0 - 2.0 * w, w);
  const double k = p[kTagToneCurve];
  for (cv::Mat* image : {&d.filtered, &d.codes, &d.slope, &d.by_strength,
                         &d.soft, &d.sharpened}) {
    image->create(d.region.size(), CV_64F);
  }
  const int cols = d.region.width;
  ForEachBand(d.region.height, [&](const cv::Range& band) {
    cv::Mat filtered = d.filtered.rowRange(band);
    Separable(d.light.light.rowRange(band), d.taps, d.taps, &filtered);
    for (int i = band.start * cols; i < band.end * cols; ++i) {
      const double m = d.filtered.ptr<double>()[i];
      const double c = std::clamp(
          FromLinear(encoding_.transfer, std::clamp(m, 0.0, 1.0)), 0.0, 1.0);
      d.codes.ptr<double>()[i] = (1.0 - k) * c + k * c * c * (3.0 - 2.0 * c);
      d.slope.ptr<double>()[i] = ((1.0 - k) + 6.0 * k * c * (1.0 - c)) *
                                 FromLinearSlope(encoding_.transfer, m);
      d.by_strength.ptr<double>()[i] = c * c * (3.0 - 2.0 * c) - c;
    }
  });
  // Unsharp-mask sharpening on the codes; the camera's codes clip at black
  // and white (its R'G'B' do, before they become luma), which hides the
  // halos of ink and paper.
  const double a = p[kTagSharpenAmount];
  std::tie(d.gaussian, d.d_gaussian) =
      GaussianAndDerivative(p[kTagSharpenRadius]);
  ForEachBand(d.region.height, [&](const cv::Range& band) {
    const cv::Mat codes = d.codes.rowRange(band);
    cv::Mat soft = d.soft.rowRange(band);
    cv::Mat sharpened = d.sharpened.rowRange(band);
    Separable(codes, d.gaussian, d.gaussian, &soft);
    cv::addWeighted(codes, 1.0 + a, soft, -a, 0.0, sharpened);
  });
  return d;
}

void TagImageCost::Residuals(const Drawn& drawn, double* residuals) const {
  const std::vector<int>& at = drawn.at;
  const double span = white_level_ - black_level_;
  const double* model = drawn.sharpened.ptr<double>();
  const double* data = data_.ptr<double>();
  for (size_t i = 0; i < fitted_.size(); ++i) {
    residuals[i] = black_level_ + span * std::clamp(model[at[i]], 0.0, 1.0) -
                   data[fitted_[i]];
  }
}

bool TagImageCost::Evaluate(double const* const* parameters, double* residuals,
                            double** jacobians) const {
  const Drawn& drawn = DrawnAt(parameters[0]);
  Residuals(drawn, residuals);
  if (jacobians != nullptr && jacobians[0] != nullptr) {
    JacobianRows(drawn, jacobians[0]);
  }
  return true;
}

double TagImageCost::SquaredNormAt(const double* params) const {
  Drawn& drawn = DrawnAt(params);
  drawn.residuals.resize(fitted_.size());
  Residuals(drawn, drawn.residuals.data());
  const Eigen::Map<const Eigen::VectorXd> r(drawn.residuals.data(),
                                            drawn.residuals.size());
  return r.squaredNorm();
}

void TagImageCost::NormalEquationsAt(const double* params,
                                     NormalEquations* out) const {
  Drawn& drawn = DrawnAt(params);
  const int n = static_cast<int>(fitted_.size());
  drawn.residuals.resize(n);
  drawn.jacobian.resize(static_cast<size_t>(n) * kTagNumParams);
  Residuals(drawn, drawn.residuals.data());
  JacobianRows(drawn, drawn.jacobian.data());
  // Sums over blocks of a fixed number of pixels, on all cores, added in
  // order: the same numbers on any number of cores.
  constexpr int kBlock = 2048;
  const int blocks = (n + kBlock - 1) / kBlock;
  std::vector<NormalEquations> partial(blocks);
  cv::parallel_for_(cv::Range(0, blocks), [&](const cv::Range& range) {
    for (int b = range.start; b < range.end; ++b) {
      const int i_0 = b * kBlock, rows = std::min(n, i_0 + kBlock) - i_0;
      const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic,
                                           kTagNumParams, Eigen::RowMajor>>
          j(drawn.jacobian.data() + static_cast<ptrdiff_t>(i_0) * kTagNumParams,
            rows, kTagNumParams);
      const Eigen::Map<const Eigen::VectorXd> r(drawn.residuals.data() + i_0,
                                                rows);
      partial[b].squared_norm = r.squaredNorm();
      // The lower half only (a symmetric rank update: half the products of
      // J^T J in full).
      partial[b].jtj.selfadjointView<Eigen::Lower>().rankUpdate(j.transpose());
      partial[b].jtr.noalias() = j.transpose() * r;
    }
  });
  *out = NormalEquations();
  for (const NormalEquations& p : partial) {
    out->squared_norm += p.squared_norm;
    out->jtj += p.jtj;
    out->jtr += p.jtr;
  }
  out->jtj.triangularView<Eigen::StrictlyUpper>() = out->jtj.transpose();
}

void TagImageCost::JacobianRows(const Drawn& drawn, double* jacobian) const {
  const double* p = drawn.params.data();
  const std::vector<int>& at = drawn.at;
  const double span = white_level_ - black_level_;
  const double* model = drawn.sharpened.ptr<double>();
  const Light& light = drawn.light;
  const cv::Mat& codes = drawn.codes;
  const cv::Mat& slope = drawn.slope;
  const cv::Mat& taps = drawn.taps;
  const cv::Mat& gaussian = drawn.gaussian;
  const cv::Mat& d_gaussian = drawn.d_gaussian;
  const double a = p[kTagSharpenAmount];
  const cv::Mat d_taps = (cv::Mat_<double>(3, 1) << 1.0, -2.0, 1.0);
  const int rows = drawn.region.height, cols = drawn.region.width;
  const int halo = gaussian.rows / 2;  // the sharpening's reach
  // d residual / d parameter, by bands of the region's rows: each core
  // filters every column over its band (and the sharpening's reach beyond
  // it) in scratch images it reuses from column to column, and writes its
  // fitted pixels' rows of the Jacobian straight into `jacobian`. Before,
  // the columns were split between cores and gathered in a column-major
  // copy that was then transposed: 2 MB of fresh pages on the first Jacobian
  // inside `validate` (docs/benchmarks.md, "The tag fitted whole: its
  // cost").
  ForEachBand(rows, [&](const cv::Range& band) {
    // Reused by this band's columns: two over the wide band, two over the
    // band.
    cv::Mat wide_a, wide_b, one, out;
    const cv::Range wide(std::max(0, band.start - halo),
                         std::min(rows, band.end + halo));
    const cv::Range in_wide(band.start - wide.start, band.end - wide.start);
    // The fitted pixels in the band: `at` rises with the row.
    const int i_0 = static_cast<int>(
        std::partition_point(at.begin(), at.end(),
                             [&](int k) { return k < band.start * cols; }) -
        at.begin());
    const int i_1 = static_cast<int>(
        std::partition_point(at.begin(), at.end(),
                             [&](int k) { return k < band.end * cols; }) -
        at.begin());
    // d sharpened over the band from d codes over the wide band, into
    // `out`: the unsharp mask is linear.
    const auto sharpen = [&](const cv::Mat& d_codes_wide) {
      const cv::Mat d_codes = d_codes_wide.rowRange(in_wide);
      Separable(d_codes, gaussian, gaussian, &one);
      cv::addWeighted(d_codes, 1.0 + a, one, -a, 0.0, out);
    };
    for (int j = 0; j < kTagNumParams; ++j) {
      if (j < kLightParams) {
        Separable(light.d_light[j].rowRange(wide), taps, taps, &wide_a);
        cv::multiply(slope.rowRange(wide), wide_a, wide_b);
        sharpen(wide_b);
      } else if (j == kTagPixelFilter) {
        const cv::Mat lit = light.light.rowRange(wide);
        Separable(lit, d_taps, taps, &wide_a);
        Separable(lit, taps, d_taps, &wide_b);
        cv::add(wide_a, wide_b, wide_a);
        cv::multiply(slope.rowRange(wide), wide_a, wide_b);
        sharpen(wide_b);
      } else if (j == kTagToneCurve) {
        sharpen(drawn.by_strength.rowRange(wide));
      } else if (j == kTagSharpenAmount) {
        cv::subtract(codes.rowRange(band), drawn.soft.rowRange(band), out);
      } else {  // kTagSharpenRadius
        const cv::Mat c = codes.rowRange(band);
        Separable(c, d_gaussian, gaussian, &one);
        Separable(c, gaussian, d_gaussian, &out);
        cv::addWeighted(one, -a, out, -a, 0.0, out);
      }
      // Zero where the codes clip.
      const double* d = out.ptr<double>();
      const int first = band.start * cols;
      double* row = jacobian + static_cast<ptrdiff_t>(i_0) * kTagNumParams + j;
      for (int i = i_0; i < i_1; ++i, row += kTagNumParams) {
        const double m = model[at[i]];
        *row = m > 0.0 && m < 1.0 ? span * d[at[i] - first] : 0.0;
      }
    }
  });
}

void SquareRootForm(const NormalEquations& equations, double* residuals,
                    double* jacobian) {
  using Matrix = NormalEquations::Matrix;
  using Vector = NormalEquations::Vector;
  // J^T J = P^T L D L^T P (pivoted, for a semidefinite J^T J: a table not in
  // view leaves its level's column zero). R = D^(1/2) L^T P; R^T z = J^T r
  // gives z = D^(-1/2) L^-1 P J^T r.
  const Eigen::LDLT<Matrix> ldlt(equations.jtj);
  Matrix permutation = Matrix::Identity();
  permutation = ldlt.transpositionsP() * permutation;
  const Matrix upper = ldlt.matrixU();
  const Vector pivots = ldlt.vectorD();
  const Vector y = ldlt.matrixL().solve(permutation * equations.jtr);
  // Pivots this far under the largest are rounding of a zero one.
  const double floor = 1e-14 * pivots.cwiseAbs().maxCoeff();
  Eigen::Map<
      Eigen::Matrix<double, kTagNumParams + 1, kTagNumParams, Eigen::RowMajor>>
      r(jacobian);
  r.setZero();
  double explained = 0.0;
  for (int k = 0; k < kTagNumParams; ++k) {
    residuals[k] = 0.0;
    if (!(pivots[k] > floor)) continue;
    const double root = std::sqrt(pivots[k]);
    r.row(k) = root * (upper.row(k) * permutation);
    residuals[k] = y[k] / root;
    explained += residuals[k] * residuals[k];
  }
  residuals[kTagNumParams] =
      std::sqrt(std::max(0.0, equations.squared_norm - explained));
}

TagImageNormalCost::TagImageNormalCost(std::unique_ptr<TagImageCost> pixels)
    : pixels_(std::move(pixels)) {}

bool TagImageNormalCost::Evaluate(double const* const* parameters,
                                  double* residuals, double** jacobians) const {
  if (jacobians == nullptr || jacobians[0] == nullptr) {
    std::fill(residuals, residuals + kTagNumParams + 1, 0.0);
    residuals[0] = std::sqrt(pixels_->SquaredNormAt(parameters[0]));
    return true;
  }
  NormalEquations equations;
  pixels_->NormalEquationsAt(parameters[0], &equations);
  SquareRootForm(equations, residuals, jacobians[0]);
  return true;
}

}  // namespace softbench
