#include "vision/static_patches.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "util/check.h"
#include "vision/luma.h"

namespace softbench {

std::optional<std::string> StaticPatchOptions::Problem() const {
  if (!(cell_px >= 8.0)) return "cell_px must be >= 8";
  if (max_patches < 0) return "max_patches must be >= 0";
  if (half_size_px < 3) return "half_size_px must be >= 3";
  if (!(min_slope_dn_per_px > 0.0)) return "min_slope_dn_per_px must be > 0";
  if (max_iterations < 1) return "max_iterations must be >= 1";
  if (!(tolerance_px > 0.0)) return "tolerance_px must be > 0";
  if (!(max_relative_residual > 0.0)) {
    return "max_relative_residual must be > 0";
  }
  return std::nullopt;
}

namespace {

// A cell's strongest point of structure and the structure tensor summed
// over a patch there.
struct Candidate {
  double strength;
  int u, v;
  float xx, yy, xy;
};

// The strongest point of each cell of the frame (codes in `encoding`) that
// `allowed` allows whole and that has at least `min_energy`. Keeps patches a
// template and a bump
// (`border`) away from the frame's edges, which also keeps every sum here
// away from them: the box reaches h rows and the slopes one more.
std::vector<Candidate> StrongestPerCell(const cv::Mat& luma,
                                        const LumaEncoding& encoding,
                                        const cv::Mat& allowed, int h, int cell,
                                        int border, double min_energy) {
  const int side = 2 * h + 1;
  std::vector<Candidate> candidates;
  // The structure tensor summed over a patch, for one row of cells at a
  // time: the band's rows plus the box's and the slopes' reach, as a view
  // into that margin so the filters read the real rows beyond the band
  // (every sum here is exact in the double sums boxFilter keeps, so the
  // values are those of the whole frame at once). A whole 1080p frame took
  // seven 8 MB float images and 0.3 s, mostly the kernel mapping fresh
  // pages; at 4K, 230 MB.
  cv::Mat image, gx, gy, product, xx, yy, xy;
  const bool masked = !allowed.empty();
  for (int y0 = border; y0 + cell <= luma.rows - border; y0 += cell) {
    const cv::Range slopes(y0 - h, y0 + cell + h), band(h, h + cell);
    // Into the same buffer every band: a fresh half-megabyte image per band
    // is mapped anew by the kernel, which cost as much as the filters.
    LumaAsFloat(luma.rowRange(slopes.start - 1, slopes.end + 1), encoding,
                &image);
    const cv::Mat inner = image.rowRange(1, image.rows - 1);
    cv::Sobel(inner, gx, CV_32F, 1, 0, 3, 1.0 / 8.0);
    cv::Sobel(inner, gy, CV_32F, 0, 1, 3, 1.0 / 8.0);
    const auto box_sum = [&](const cv::Mat& a, const cv::Mat& b, cv::Mat* out) {
      cv::multiply(a, b, product);
      cv::boxFilter(product.rowRange(band), *out, CV_32F, cv::Size(side, side),
                    {-1, -1}, false);
    };
    box_sum(gx, gx, &xx);
    box_sum(gy, gy, &yy);
    box_sum(gx, gy, &xy);
    for (int x0 = border; x0 + cell <= luma.cols - border; x0 += cell) {
      Candidate best{0.0, -1, -1, 0, 0, 0};
      for (int r = 0; r < cell; ++r) {
        const int v = y0 + r;
        const auto* a = xx.ptr<float>(r);
        const auto* b = yy.ptr<float>(r);
        const auto* c = xy.ptr<float>(r);
        const uint8_t* ok = masked ? allowed.ptr<uint8_t>(v) : nullptr;
        for (int u = x0; u < x0 + cell; ++u) {
          if (ok != nullptr && ok[u] == 0) continue;
          if (a[u] + b[u] > best.strength) {
            best = {a[u] + b[u], u, v, a[u], b[u], c[u]};
          }
        }
      }
      // The patch must be allowed whole, not just at its centre.
      if (best.u < 0 || best.strength < min_energy) continue;
      if (masked && cv::countNonZero(allowed(cv::Rect(
                        best.u - h, best.v - h, side, side))) < side * side) {
        continue;
      }
      candidates.push_back(best);
    }
  }
  return candidates;
}

}  // namespace

StaticPatches::StaticPatches(const cv::Mat& luma, const cv::Mat& allowed,
                             const StaticPatchOptions& options)
    : options_(options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  const int h = options.half_size_px, side = 2 * h + 1;
  const std::vector<float>& linear =
      LinearLumaTable(options.luma_encoding, luma.depth());
  const double min_energy =
      options.min_slope_dn_per_px * options.min_slope_dn_per_px * side * side;
  const int border = 2 * h + 8;  // a template and a bump
  std::vector<Candidate> candidates =
      StrongestPerCell(luma, options.luma_encoding, allowed, h,
                       static_cast<int>(options.cell_px), border, min_energy);
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& a, const Candidate& b) {
              return a.strength > b.strength;
            });
  for (const Candidate& c : candidates) {
    if (static_cast<int>(templates_.size()) >= options.max_patches) break;
    Eigen::Matrix2d tensor;
    tensor << c.xx, c.xy, c.xy, c.yy;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(tensor);
    Template t;
    t.centre = Eigen::Vector2d(c.u, c.v);
    // A corner when the weaker direction is strong too; else an edge,
    // measured across itself only.
    const double weak = eigen.eigenvalues()[0], strong = eigen.eigenvalues()[1];
    if (weak < min_energy) {
      // A straight edge only (its slope along itself under a tenth of that
      // across): a curved one, measured along one normal, is biased.
      if (weak > 0.1 * strong) continue;
      t.normal = eigen.eigenvectors().col(1).normalized();
    }
    const cv::Rect box(c.u - h - 1, c.v - h - 1, side + 2, side + 2);
    const cv::Mat region = LinearLuma(luma(box), linear);
    cv::Scalar mean, stddev;
    cv::meanStdDev(region(cv::Rect(1, 1, side, side)), mean, stddev);
    t.contrast = stddev[0];
    for (int v = 1; v <= side; ++v) {
      const float* above = region.ptr<float>(v - 1);
      const float* row = region.ptr<float>(v);
      const float* below = region.ptr<float>(v + 1);
      for (int u = 1; u <= side; ++u) {
        // Central differences, the same as the bilinear image's slope.
        const float dx = 0.5f * (row[u + 1] - row[u - 1]);
        const float dy = 0.5f * (below[u] - above[u]);
        t.values.push_back(row[u]);
        if (t.normal == Eigen::Vector2d::Zero()) {
          t.slope_x.push_back(dx);
          t.slope_y.push_back(dy);
        } else {  // an edge: the slope across it only
          t.slope_x.push_back(
              static_cast<float>(dx * t.normal.x() + dy * t.normal.y()));
          t.slope_y.push_back(0.0f);
        }
      }
    }
    t.normal_matrix = Eigen::Matrix4d::Zero();
    for (int i = 0; i < side * side; ++i) {
      const Eigen::Vector4d j = Jacobian(t, i);
      t.normal_matrix += j * j.transpose();
    }
    if (t.normal != Eigen::Vector2d::Zero()) t.normal_matrix(1, 1) = 1.0;
    templates_.push_back(std::move(t));
  }
}

std::vector<Eigen::Vector2d> StaticPatches::reference_px() const {
  std::vector<Eigen::Vector2d> centres;
  for (const Template& t : templates_) centres.push_back(t.centre);
  return centres;
}

Eigen::Vector4d StaticPatches::Jacobian(const Template& t, int i) {
  return {t.slope_x[i], t.slope_y[i], -t.values[i], -1.0};
}

bool StaticPatches::Align(const cv::Mat& luma, const Template& t,
                          Scratch* scratch, Eigen::Vector2d* centre) const {
  const int h = options_.half_size_px, side = 2 * h + 1, n = side * side;
  const bool edge = t.normal != Eigen::Vector2d::Zero();
  // Parameters: the shift (along the normal for an edge) and a photometric
  // gain and offset, luma(x + d) = gain * template(x) + offset.
  double gain = 1.0, offset = 0.0;
  Eigen::Vector2d d = *centre;
  const std::vector<float>& linear =
      LinearLumaTable(options_.luma_encoding, luma.depth());
  const Eigen::Map<const Eigen::ArrayXf> values(t.values.data(), n);
  const Eigen::Map<const Eigen::ArrayXf> slope_x(t.slope_x.data(), n);
  const Eigen::Map<const Eigen::ArrayXf> slope_y(t.slope_y.data(), n);
  std::vector<float>& light = scratch->light;
  light.resize(static_cast<size_t>(side + 1) * (side + 1));
  scratch->residual.resize(n);
  Eigen::Map<Eigen::ArrayXf> residual(scratch->residual.data(), n);
  int light_x = 0, light_y = 0;  // the pixel `light` starts at
  double rms = 0.0;
  for (int iteration = 0; iteration < options_.max_iterations; ++iteration) {
    const double x0 = d.x() - h, y0 = d.y() - h;
    const int ix = static_cast<int>(std::floor(x0)),
              iy = static_cast<int>(std::floor(y0));
    if (ix < 0 || iy < 0 || ix + side >= luma.cols || iy + side >= luma.rows) {
      return false;
    }
    // Each pixel under the patch through the linear table once (not once
    // per bilinear sample that reads it), and again only when the patch
    // has moved to other pixels (a step of a hundredth of a pixel rarely
    // does); then the samples and the sums as float arrays. This runs for
    // every patch of every frame, and vectorised it takes about a quarter of
    // the time of the per-pixel loop it replaced.
    if (iteration == 0 || ix != light_x || iy != light_y) {
      WithLumaType(luma, [&](auto type) {
        using T = decltype(type);
        for (int v = 0; v <= side; ++v) {
          const T* row = luma.ptr<T>(iy + v) + ix;
          float* out = &light[static_cast<size_t>(v) * (side + 1)];
          for (int u = 0; u <= side; ++u) out[u] = linear[row[u]];
        }
      });
      light_x = ix, light_y = iy;
    }
    const auto a = static_cast<float>(x0 - ix), b = static_cast<float>(y0 - iy);
    const auto g = static_cast<float>(gain), o = static_cast<float>(offset);
    for (int v = 0; v < side; ++v) {
      const float* l0 = &light[static_cast<size_t>(v) * (side + 1)];
      const float* l1 = l0 + side + 1;
      const float* tv = &t.values[static_cast<size_t>(v) * side];
      float* r = &scratch->residual[static_cast<size_t>(v) * side];
      for (int u = 0; u < side; ++u) {
        const float sample = (1 - b) * ((1 - a) * l0[u] + a * l0[u + 1]) +
                             b * ((1 - a) * l1[u] + a * l1[u + 1]);
        r[u] = sample - g * tv[u] - o;
      }
    }
    // The right-hand side, minus the sum of Jacobian * residual.
    Eigen::Vector4d rhs(-(slope_x * residual).sum(),
                        edge ? 0.0 : -(slope_y * residual).sum(),
                        (values * residual).sum(), residual.sum());
    const double squares = residual.square().sum();
    rms = std::sqrt(squares / n);
    // d residual / d (shift, gain, offset) is the unit-gain Jacobian with
    // its shift part scaled by the gain (the image's slope taken as the
    // template's near the solution).
    const Eigen::Vector4d scale(gain, edge ? 1.0 : gain, 1.0, 1.0);
    rhs = rhs.cwiseProduct(scale);
    const Eigen::Matrix4d normal =
        scale.asDiagonal() * t.normal_matrix * scale.asDiagonal();
    const Eigen::Vector4d step = normal.ldlt().solve(rhs);
    if (!step.allFinite()) return false;
    const Eigen::Vector2d shift =
        edge ? Eigen::Vector2d(step[0] * t.normal) : step.head<2>();
    d += shift;
    gain += step[2];
    offset += step[3];
    if ((d - *centre).norm() > h) return false;  // ran off: not this patch
    if (shift.norm() < options_.tolerance_px) break;
  }
  if (!(gain > 0.2) ||
      rms > options_.max_relative_residual * t.contrast * gain) {
    return false;
  }
  *centre = d;
  return true;
}

std::vector<PatchMatch> StaticPatches::Track(
    const cv::Mat& luma, const std::vector<Eigen::Vector2d>& predicted) const {
  std::vector<PatchMatch> matches(templates_.size());
  // Kept for the thread's life: this runs every frame, and buffers of a
  // kilobyte or more, made afresh, make malloc sort its free lists each time.
  thread_local Scratch scratch;
  for (size_t i = 0; i < templates_.size(); ++i) {
    PatchMatch& m = matches[i];
    m.reference_px = templates_[i].centre;
    m.normal = templates_[i].normal;
    m.pixel = predicted[i];
    m.found = Align(luma, templates_[i], &scratch, &m.pixel);
  }
  return matches;
}

}  // namespace softbench
