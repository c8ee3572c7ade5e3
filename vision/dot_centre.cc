#include "vision/dot_centre.h"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <vector>

#include "vision/luma.h"

namespace softbench {

std::optional<std::string> DotCentreOptions::Problem() const {
  if (!(window_margin_px >= 0.5)) return "window_margin_px must be >= 0.5";
  if (!(background_width_px >= 1.0)) return "background_width_px must be >= 1";
  if (max_iterations < 1) return "max_iterations must be >= 1";
  if (!(tolerance_px > 0.0)) return "tolerance_px must be > 0";
  if (!(min_contrast > 0.0)) return "min_contrast must be > 0";
  return std::nullopt;
}

namespace {

// A pixel of the step's box, relative to the current centre.
struct BoxPixel {
  double dx, dy, d2, luma;
};

// The pixels within `outer` of the centre c, each with its linear luma (its
// code in 8-bit levels with `weigh_codes`): the ring outside the window
// (background) into `ring`, the window itself (the dot) into `inside`.
void GatherBox(const cv::Mat& luma, const Eigen::Vector2d& c, double window,
               double outer, const LumaEncoding& encoding, bool weigh_codes,
               std::vector<BoxPixel>* ring, std::vector<BoxPixel>* inside) {
  const int x0 = static_cast<int>(std::floor(c.x() - outer)),
            x1 = static_cast<int>(std::ceil(c.x() + outer)),
            y0 = static_cast<int>(std::floor(c.y() - outer)),
            y1 = static_cast<int>(std::ceil(c.y() + outer));
  // The pixels within `outer` of the centre, gathered once: the ring
  // outside the window (background) and the window itself (the dot).
  // Distances are compared squared; the square root is taken only on the
  // window's soft edge, where the weight needs it.
  ring->clear();
  inside->clear();
  const double outer_sq = outer * outer, window_sq = window * window;
  const double inside_sq = (window + 0.5) * (window + 0.5);
  WithLumaType(luma, [&](auto type) {
    using T = decltype(type);
    const std::vector<float>& linear =
        LinearLumaTable(encoding, cv::DataType<T>::depth);
    // Codes from black (limited range's 16), so that lighting scales a
    // dot's code and its background's alike, as it does their light.
    const double black = BlackLevel(encoding);
    const double levels_per_code = LevelsPerCode(luma.depth(), encoding);
    for (int y = y0; y <= y1; ++y) {
      const T* row = luma.ptr<T>(y);
      const double dy = y - c.y();
      for (int x = x0; x <= x1; ++x) {
        const double dx = x - c.x();
        const double d2 = dx * dx + dy * dy;
        if (d2 > outer_sq) continue;
        const BoxPixel p{
            dx, dy, d2,
            weigh_codes ? levels_per_code * row[x] - black : linear[row[x]]};
        if (d2 >= window_sq) ring->push_back(p);
        if (d2 < inside_sq) inside->push_back(p);
      }
    }
  });
}

// The background plane L = a + b dx + c dy fitted to the ring and its RMS
// residual; false when too few pixels are left.
bool FitBackgroundPlane(const std::vector<BoxPixel>& ring,
                        Eigen::Vector3d* plane_out, double* noise_out) {
  // Background plane L = a + b dx + c dy on the ring [window, outer], with
  // one pass rejecting outliers (a glint, a neighbouring edge).
  Eigen::Vector3d& plane = *plane_out;
  double& noise = *noise_out;
  plane.setZero();
  noise = 0.0;
  for (int pass = 0; pass < 2; ++pass) {
    // Sums of the normal equations in the basis (1, dx, dy).
    double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
    double sl = 0, sxl = 0, syl = 0, sum_sq = 0;
    for (const BoxPixel& p : ring) {
      if (pass == 1 &&
          std::abs(p.luma - (plane[0] + plane[1] * p.dx + plane[2] * p.dy)) >
              3.0 * noise + 1.0) {
        continue;
      }
      n += 1;
      sx += p.dx;
      sy += p.dy;
      sxx += p.dx * p.dx;
      sxy += p.dx * p.dy;
      syy += p.dy * p.dy;
      sl += p.luma;
      sxl += p.dx * p.luma;
      syl += p.dy * p.luma;
      sum_sq += p.luma * p.luma;
    }
    if (n < 12) return false;
    Eigen::Matrix3d normal;
    normal << n, sx, sy, sx, sxx, sxy, sy, sxy, syy;
    const Eigen::Vector3d rhs(sl, sxl, syl);
    plane = normal.ldlt().solve(rhs);
    // RMS residual of the least-squares fit: sum(L^2) - plane . rhs.
    noise = std::sqrt(std::max(0.0, (sum_sq - plane.dot(rhs)) / (n - 3)));
  }
  return true;
}

// One weighted-centroid step around `c`; false (with a reason) when the
// window leaves the image or the contrast is too low.
bool CentroidStep(const cv::Mat& luma, const Eigen::Vector2d& c,
                  double radius_px, const DotCentreOptions& options,
                  DotCentre* out, Eigen::Vector2d* next) {
  const double window = radius_px + options.window_margin_px;
  const double outer = window + options.background_width_px;
  const int x0 = static_cast<int>(std::floor(c.x() - outer)),
            x1 = static_cast<int>(std::ceil(c.x() + outer)),
            y0 = static_cast<int>(std::floor(c.y() - outer)),
            y1 = static_cast<int>(std::ceil(c.y() + outer));
  if (x0 < 0 || y0 < 0 || x1 >= luma.cols || y1 >= luma.rows) {
    out->why_not = "too close to the image border";
    return false;
  }
  // The buffers live as long as the thread, so a step allocates nothing.
  thread_local std::vector<BoxPixel> ring, inside;
  GatherBox(luma, c, window, outer, options.luma_encoding, options.weigh_codes,
            &ring, &inside);
  Eigen::Vector3d plane;
  double noise = 0.0;
  if (!FitBackgroundPlane(ring, &plane, &noise)) {
    out->why_not = "too few background pixels around the dot";
    return false;
  }
  // Lighting multiplies the dot and the head alike, so the dot's level is a
  // fixed fraction `ratio` of the local background.
  const auto background = [&](const BoxPixel& p) {
    return plane[0] + plane[1] * p.dx + plane[2] * p.dy;
  };
  const double inner_fg = std::max(0.5 * radius_px, radius_px - 1.5);
  const double inner_fg_sq = inner_fg * inner_fg;
  double ratio_sum = 0.0;
  int fg_count = 0;
  for (const BoxPixel& p : inside) {
    if (p.d2 <= inner_fg_sq) {
      ratio_sum += p.luma / background(p);
      ++fg_count;
    }
  }
  if (fg_count == 0 || !(plane[0] > 0.0)) {
    out->why_not = "the dot is too small to sample its interior";
    return false;
  }
  const double ratio = ratio_sum / fg_count;
  const double contrast = plane[0] * (1.0 - ratio);
  out->contrast = contrast;
  out->noise_level = noise;
  if (std::abs(contrast) < options.min_contrast) {
    out->why_not = fmt::format(
        "luma contrast {:.1f} levels between dot and head is below {:.0f}",
        contrast, options.min_contrast);
    return false;
  }
  // Coverage-weighted centroid inside the soft window; the coverage of a
  // pixel is (1 - luma / background) / (1 - ratio).
  const double full_sq = (window - 0.5) * (window - 0.5);
  double sw = 0.0, swx = 0.0, swy = 0.0, s2xx = 0.0, s2yy = 0.0;
  for (const BoxPixel& p : inside) {
    const double s = p.d2 <= full_sq
                         ? 1.0
                         : std::clamp(window + 0.5 - std::sqrt(p.d2), 0.0, 1.0);
    if (s == 0.0) continue;
    const double w = s * (1.0 - p.luma / background(p)) / (1.0 - ratio);
    sw += w;
    swx += w * p.dx;
    swy += w * p.dy;
    s2xx += s * s * p.dx * p.dx;
    s2yy += s * s * p.dy * p.dy;
  }
  if (!(sw > 0.0)) {
    out->why_not = "no dot coverage in the window";
    return false;
  }
  *next = c + Eigen::Vector2d(swx / sw, swy / sw);
  // Each weight carries noise / contrast; propagated through the centroid.
  const double k = noise / std::abs(contrast) / sw;
  out->sigma_px = k * std::sqrt(0.5 * (s2xx + s2yy));
  return true;
}

}  // namespace

DotCentre LocateDotCentre(const cv::Mat& luma, const Eigen::Vector2d& start,
                          double radius_px, const DotCentreOptions& options) {
  DotCentre result;
  Eigen::Vector2d c = start;
  for (int i = 0; i < options.max_iterations; ++i) {
    Eigen::Vector2d next;
    result.iterations = i + 1;
    if (!CentroidStep(luma, c, radius_px, options, &result, &next)) {
      return result;
    }
    const double moved = (next - c).norm();
    c = next;
    if (moved > radius_px) {
      result.why_not = "the centre ran off the dot (is it the right size?)";
      return result;
    }
    if (moved < options.tolerance_px) break;
  }
  result.found = true;
  result.centre = c;
  return result;
}

}  // namespace softbench
