#include "vision/tag_detector.h"

#include <apriltag/apriltag.h>
#include <apriltag/tag36h11.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#if defined(__SSE2__)
#include <emmintrin.h>
#include <xmmintrin.h>
#endif
#include <algorithm>
#include <array>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <vector>

#include "util/check.h"
#include "util/statistics.h"
#include "vision/color_transfer.h"
#include "vision/frame_source.h"
#include "vision/luma.h"

namespace softbench {

std::optional<std::string> TagDetectorOptions::Problem() const {
  if (!(edge_half_width_px >= 2.0)) return "edge_half_width_px must be >= 2";
  if (!(quad_decimate >= 1.0f)) return "quad_decimate must be >= 1";
  return std::nullopt;
}

namespace {

// Fits of the border per detection, each from the last one's corners.
constexpr int kMaxBorderFits = 4;

// The linear light (options.luma_encoding) of the part of a frame that a
// tag's edge profiles read, converted once per fit of its border: the
// profiles sample every pixel near an edge many times over, and each sample
// read four pixels through the transfer table.
struct LinearRegion {
  cv::Mat light;     // CV_32FC1, a view into the buffer it was converted in
  cv::Point origin;  // the region's top-left pixel in the frame
  double levels_per_code = 1.0;  // of the frame's codes (LevelsPerCode)
};

// The region around corners known to a few pixels: the border's profiles
// reach at most `reach_px` beyond the sides they are taken from. Converted
// into `buffer`, which grows but is not given back: a new region for every
// frame cost a large allocation (and glibc's consolidation of its free
// chunks) each time.
LinearRegion LinearRegionAround(const cv::Mat& gray,
                                const std::array<Eigen::Vector2d, 4>& corners,
                                double reach_px, const LumaEncoding& encoding,
                                cv::Mat* buffer) {
  // Two pixels more: a bilinear sample reads the pixel after its own.
  const cv::Rect box =
      BoxAround({corners.begin(), corners.end()}, reach_px + 2, gray.size());
  if (box.empty()) return {};
  if (buffer->rows < box.height || buffer->cols < box.width) {
    buffer->create(std::max(buffer->rows, box.height),
                   std::max(buffer->cols, box.width), CV_32FC1);
  }
  cv::Mat light = (*buffer)(cv::Rect(0, 0, box.width, box.height));
  LinearLuma(gray(box), LinearLumaTable(encoding, gray.depth()), &light);
  return {light, box.tl(), LevelsPerCode(gray.depth(), encoding)};
}

// A profile across an edge: samples every kStep at offsets s from -d to d
// along its normal (the same for every profile of a side), and one buffer
// for the samples, as this runs for every frame's tag.
struct Profile {
  static constexpr double kStep = 0.25;
  // The half-length is a whole number of steps, so that the samples reach
  // from -d to d exactly (the integral's edge is measured from -d).
  explicit Profile(double half_length)
      : d(std::floor(half_length / kStep) * kStep) {
    offsets.reserve(static_cast<size_t>(2 * d / kStep) + 2);
    for (double s = -d; s <= d + 1e-9; s += kStep) {
      offsets.push_back(static_cast<float>(s));
    }
    values.resize(offsets.size());
  }
  double d;
  std::vector<float> offsets;
  std::vector<double> values;
};

// Bilinear samples of `region` at start + s normal for each offset s, into
// `values`; every sample must lie in the region, where q >= 0, so that
// truncation is floor (a call to floor, without SSE 4.1's roundsd, was a
// tenth of this loop's time). In float, with positions from the region's
// corner (under 1e-5 px of rounding, where the edges are found to 1e-3),
// four samples at a time where SSE2 is: each sample's two pixels of a row
// are one 8-byte load. The same operations in the same order as one at a
// time, so the results are the same to the bit.
void SampleProfile(const LinearRegion& region, const Eigen::Vector2d& start,
                   const Eigen::Vector2d& normal,
                   const std::vector<float>& offsets,
                   std::vector<double>* values) {
  const float* light = region.light.ptr<float>();
  const size_t stride = region.light.step1();
  const int n = static_cast<int>(offsets.size());
  double* out = values->data();
  const auto sx = static_cast<float>(start.x()),
             sy = static_cast<float>(start.y());
  const auto nx = static_cast<float>(normal.x()),
             ny = static_cast<float>(normal.y());
  int k = 0;
#if defined(__SSE2__)
  const __m128 vsx = _mm_set1_ps(sx), vsy = _mm_set1_ps(sy);
  const __m128 vnx = _mm_set1_ps(nx), vny = _mm_set1_ps(ny);
  const __m128 one = _mm_set1_ps(1.0f);
  alignas(16) int ix[4], iy[4];
  for (; k + 4 <= n; k += 4) {
    const __m128 s = _mm_loadu_ps(&offsets[k]);
    const __m128 qx = _mm_add_ps(vsx, _mm_mul_ps(s, vnx));
    const __m128 qy = _mm_add_ps(vsy, _mm_mul_ps(s, vny));
    const __m128i jx = _mm_cvttps_epi32(qx), jy = _mm_cvttps_epi32(qy);
    const __m128 a = _mm_sub_ps(qx, _mm_cvtepi32_ps(jx));
    const __m128 b = _mm_sub_ps(qy, _mm_cvtepi32_ps(jy));
    _mm_store_si128(reinterpret_cast<__m128i*>(ix), jx);
    _mm_store_si128(reinterpret_cast<__m128i*>(iy), jy);
    const float* p[4];
    for (int i = 0; i < 4; ++i) p[i] = light + iy[i] * stride + ix[i];
    // Rows as (left, right) pairs: lanes 0 and 1, then 2 and 3.
    const auto pair = [](const float* a0, const float* a1) {
      return _mm_loadh_pi(
          _mm_loadl_pi(_mm_setzero_ps(), reinterpret_cast<const __m64*>(a0)),
          reinterpret_cast<const __m64*>(a1));
    };
    const __m128 top01 = pair(p[0], p[1]), top23 = pair(p[2], p[3]);
    const __m128 bottom01 = pair(p[0] + stride, p[1] + stride);
    const __m128 bottom23 = pair(p[2] + stride, p[3] + stride);
    const __m128 r00 = _mm_shuffle_ps(top01, top23, _MM_SHUFFLE(2, 0, 2, 0));
    const __m128 r01 = _mm_shuffle_ps(top01, top23, _MM_SHUFFLE(3, 1, 3, 1));
    const __m128 r10 =
        _mm_shuffle_ps(bottom01, bottom23, _MM_SHUFFLE(2, 0, 2, 0));
    const __m128 r11 =
        _mm_shuffle_ps(bottom01, bottom23, _MM_SHUFFLE(3, 1, 3, 1));
    const __m128 ia = _mm_sub_ps(one, a), ib = _mm_sub_ps(one, b);
    const __m128 top = _mm_add_ps(_mm_mul_ps(ia, r00), _mm_mul_ps(a, r01));
    const __m128 bottom = _mm_add_ps(_mm_mul_ps(ia, r10), _mm_mul_ps(a, r11));
    const __m128 sample =
        _mm_add_ps(_mm_mul_ps(ib, top), _mm_mul_ps(b, bottom));
    _mm_storeu_pd(out + k, _mm_cvtps_pd(sample));
    _mm_storeu_pd(out + k + 2, _mm_cvtps_pd(_mm_movehl_ps(sample, sample)));
  }
#endif
  for (; k < n; ++k) {
    const float qx = sx + offsets[k] * nx, qy = sy + offsets[k] * ny;
    const int x = static_cast<int>(qx), y = static_cast<int>(qy);
    const float a = qx - static_cast<float>(x), b = qy - static_cast<float>(y);
    const float* r0 = light + y * stride + x;
    const float* r1 = r0 + stride;
    out[k] = (1 - b) * ((1 - a) * r0[0] + a * r0[1]) +
             b * ((1 - a) * r1[0] + a * r1[1]);
  }
}

// An edge found on a profile, and the profile's white level (linear light,
// the mean of its last pixel).
struct EdgeSample {
  Eigen::Vector2d point;
  double white = 0.0;
};

// Where an edge crosses the profile from p - d normal (dark) to p + d normal
// (bright), from the profile's integral:
//   offset = d - integral_{-d}^{d} (p(s) - black) ds / (white - black),
// which a symmetric blur (the lens, the pixel's area sampling,
// interpolation) does not change, unlike a threshold crossing. The profile
// is taken in linear light (`region`, which holds every pixel it reads), as
// the lens mixes light. nullopt when its ends are not clean dark and bright
// levels.
template <typename T>
std::optional<EdgeSample> EdgePoint(const cv::Mat& gray,
                                    const LinearRegion& region,
                                    const Eigen::Vector2d& p,
                                    const Eigen::Vector2d& normal,
                                    Profile* profile) {
  // The contrast is judged in codes (40 levels of 255), as a person sees
  // it, so dim footage is refined as before; judged first, as half the
  // data cells are black and have no edge to profile.
  const double d = profile->d;
  const Eigen::Vector2d inside = p - d * normal, outside = p + d * normal;
  const auto in_image = [&](const Eigen::Vector2d& q) {
    return q.x() >= 0 && q.y() >= 0 && q.x() + 1 < gray.cols &&
           q.y() + 1 < gray.rows;
  };
  if (!in_image(inside) || !in_image(outside) ||
      SampleLuma<T>(gray, outside.x(), outside.y(), region.levels_per_code) -
              SampleLuma<T>(gray, inside.x(), inside.y(),
                            region.levels_per_code) <
          40.0) {
    return std::nullopt;
  }
  // The profile is a segment, so its two ends inside the region put all of
  // it there (they always are for the profiles FitBorderSideOf takes). A
  // hundredth of a pixel to spare at the far side, as the samples are
  // placed in float.
  const Eigen::Vector2d origin(region.origin.x, region.origin.y);
  const auto in_region = [&](const Eigen::Vector2d& q) {
    const Eigen::Vector2d r = q - origin;
    return r.x() >= 0 && r.y() >= 0 && r.x() + 1.01 < region.light.cols &&
           r.y() + 1.01 < region.light.rows;
  };
  if (!in_region(inside) || !in_region(outside)) return std::nullopt;
  // Light below black is kept: a phone's sharpening undershoots the ink
  // below video black (limited range's code 16), and dropping those
  // profiles left the tag unrefined.
  SampleProfile(region, p - origin, normal, profile->offsets, &profile->values);
  const std::vector<double>& v = profile->values;
  constexpr double kStep = Profile::kStep;
  const int end = static_cast<int>(v.size()) - 1;
  const int flat = static_cast<int>(1.0 / kStep);  // 1 px at each end
  double black = 0, white = 0;
  for (int i = 0; i <= flat; ++i) {
    black += v[i] / (flat + 1);
    white += v[end - i] / (flat + 1);
  }
  if (!(white > black)) return std::nullopt;
  // The trapezoid rule, sum over i < end of (v[i] + v[i + 1]) / 2 - black,
  // as one sum of every sample (a vectorised one, not a chain of dependent
  // additions: this runs for every profile of every frame).
  const double total =
      Eigen::Map<const Eigen::ArrayXd>(v.data(), end + 1).sum();
  const double integral = (total - 0.5 * (v[0] + v[end]) - end * black) * kStep;
  return EdgeSample{p + (d - integral / (white - black)) * normal, white};
}

// How far a gain on the light that grows by `slope` (relative, per pixel)
// toward an edge's bright side moves EdgePoint's edge toward it [px]. With
// the light (1 + slope s) q(s) for the true profile q, black and white read
// as the means of the profile's first and last pixel (centred at -+(d -
// 1/2)) and the integral taken over [-d, d], the edge moves by
//   slope d (d - 1) / 2
// to first order in the slope, whatever the edge's blur: a phone's local
// tone mapping (a few tenths of a percent per pixel between a white tag and
// a dark table) moved the tag's every edge outward by 0.02-0.05 px.
double EdgeShiftFromGainSlope(double slope, double d) {
  return slope * d * (d - 1.0) / 2.0;
}

// A profile's halo (TagEdgeSigns::halo): its larger excursion beyond its
// ends, above the white (its last pixel's mean) or below the black (its
// first's), over the step between them. The larger, as either may be cut:
// a phone's white paper sits near its tone curve's shoulder or at the top
// code, and black light cannot go far below zero. (Scaling the profile
// scales both, so the sum of profiles serves as their mean.)
double HaloOf(const Eigen::ArrayXd& profile) {
  const int flat = static_cast<int>(1.0 / Profile::kStep);  // 1 px
  const double black = profile.head(flat + 1).mean();
  const double white = profile.tail(flat + 1).mean();
  if (!(white > black)) return 0.0;
  return std::max(profile.maxCoeff() - white, black - profile.minCoeff()) /
         (white - black);
}

// The white levels a side's profiles read, per data cell along the side:
// beyond the outer edge (the tag's white margin) and inside the cell when it
// is white. Both are the same paper, so their ratio is the gain on the light
// between them: a phone's local tone mapping lifts the dark table around
// the tag more than the tag (issue 28), and lighting falls off across it.
class CellWhites {
 public:
  // Empties every cell, keeping the room (a tag is fitted in every frame).
  void Clear() {
    for (std::vector<double>& cell : outer_) cell.clear();
    for (std::vector<double>& cell : inner_) cell.clear();
  }
  void AddOuter(int cell, double white) { Add(&outer_, cell, white); }
  void AddInner(int cell, double white) { Add(&inner_, cell, white); }
  // The log of the gain from the whites inside to those beyond: the mean
  // over the white cells of the log ratio of the medians, each cell's outer
  // white taken along the same stretch of the side (the gain changes along
  // it too). nullopt without a white cell.
  std::optional<double> LogRatio() const {
    double sum = 0.0;
    int cells = 0;
    for (int k = 1; k < kTagCellsAcross - 1; ++k) {
      if (inner_[k].empty() || outer_[k].empty()) continue;
      sum += std::log(Median(outer_[k]) / Median(inner_[k]));
      ++cells;
    }
    if (cells == 0) return std::nullopt;
    return sum / cells;
  }

 private:
  using Cells = std::array<std::vector<double>, kTagCellsAcross>;
  static void Add(Cells* cells, int cell, double white) {
    if (cell < 1 || cell >= kTagCellsAcross - 1 || !(white > 0.0)) return;
    (*cells)[cell].push_back(white);
  }
  Cells outer_, inner_;
};

// One side of the black border, from corner a to corner b.
struct BorderSide {
  cv::Vec4f outer;  // the outer edge's line (x0, y0 at vx, vy as fitLine's)
  Eigen::Vector2d normal;  // outward unit normal
  // The border's width across, as measured, linear in the distance t from
  // a (width_slope is zero where the data cannot say): twice the bias of
  // one edge plus the cell's true width.
  double width_at_a = 0, width_slope = 0;
  bool has_width = false;
  int sampled = 0, clean = 0;  // outer-edge profiles taken and used
  double rms_px = 0.0;         // their points' RMS distance from `outer`
  double halo = 0.0;           // the outer profiles' mean's (HaloOf)
  // log(white beyond / white inside): CellWhites::LogRatio.
  std::optional<double> white_log_ratio;
};

// The border's width along a side as a straight line through the (t,
// width) points of its white cells, into `side`: perspective changes the
// cell's width along the side by up to a few tenths of a percent per
// degree. `widths` must not be empty.
void FitWidthLine(const std::vector<Eigen::Vector2d>& widths, double cell,
                  BorderSide* side) {
  double st = 0, sw = 0;
  for (const Eigen::Vector2d& w : widths) st += w.x(), sw += w.y();
  const double n = static_cast<double>(widths.size());
  const double t_mean = st / n, w_mean = sw / n;
  double stt = 0, stw = 0;
  for (const Eigen::Vector2d& w : widths) {
    stt += (w.x() - t_mean) * (w.x() - t_mean);
    stw += (w.x() - t_mean) * (w.y() - w_mean);
  }
  // Only white cells spread along the side (by more than a cell, RMS) say
  // how the width changes.
  const bool spread = std::sqrt(stt / n) > cell;
  side->width_slope = spread ? stw / stt : 0.0;
  side->width_at_a = w_mean - side->width_slope * t_mean;
  side->has_width = true;
}

// The side's outer edge (black inside, white outside) along its middle
// 60 %, and, inside each data cell that is white, its inner edge: the
// border's width. Both edges of the one-cell bar go from black to white
// away from its middle, so anything that moves an edge toward the dark or
// the bright side (a transfer curve the metadata does not name, blur or
// sharpening applied to codes, the phone's tone curve) moves them apart or
// together by the same amount and leaves the bar's midline where it is:
// the midline, not the outer edge, is what locates the tag (issue 28;
// each alone is off by 0.4-0.6 % of the tag's size under a phone's
// sharpening or blur in codes).
template <typename T>
std::optional<BorderSide> FitBorderSideOf(const cv::Mat& gray,
                                          const LinearRegion& region,
                                          const Eigen::Vector2d& a,
                                          const Eigen::Vector2d& b,
                                          const TagDetectorOptions& options) {
  const Eigen::Vector2d along = (b - a).normalized();
  BorderSide side;
  // Outward normal: libapriltag's corners run counter-clockwise as seen on
  // screen, so with y down outward is (-along_y, along_x).
  side.normal = Eigen::Vector2d(-along.y(), along.x());
  const double length = (b - a).norm();
  const double cell = length / kTagCellsAcross;
  // Each profile's dark end must stay on the one-cell bar.
  const double d = std::min(options.edge_half_width_px, 0.45 * cell);
  Profile profile(d);
  // Profiles every half pixel, at most 160 along the middle 60 % (a 1080p
  // tag's; a 4K tag's edge gets them a pixel apart, the same spacing in
  // millimetres): this runs for every frame.
  const double spacing = std::max(0.5, 0.6 * length / 160.0);
  // Room for every profile up front (this runs for every frame).
  std::vector<cv::Point2f> points;
  points.reserve(static_cast<size_t>(0.6 * length / spacing) + 2);
  // The white beyond the outer edge and inside the white data cells, per
  // cell along the side (CellWhites::LogRatio); one per thread, reused.
  thread_local CellWhites whites;
  whites.Clear();
  // The outer profiles' sum, sample by sample: their mean shows a halo
  // with the noise of one profile divided by ~9 (TagEdgeSigns::halo).
  thread_local Eigen::ArrayXd profile_sum;
  profile_sum.setZero(static_cast<Eigen::Index>(profile.values.size()));
  for (double t = 0.2 * length; t <= 0.8 * length; t += spacing) {
    ++side.sampled;
    if (const auto edge =
            EdgePoint<T>(gray, region, a + t * along, side.normal, &profile)) {
      points.emplace_back(static_cast<float>(edge->point.x()),
                          static_cast<float>(edge->point.y()));
      whites.AddOuter(static_cast<int>(t / cell), edge->white);
      profile_sum += Eigen::Map<const Eigen::ArrayXd>(profile.values.data(),
                                                      profile_sum.size());
    }
  }
  side.clean = static_cast<int>(points.size());
  if (points.size() < 8) return std::nullopt;
  side.halo = HaloOf(profile_sum);
  cv::fitLine(points, side.outer, cv::DIST_L2, 0, 1e-6, 1e-6);
  const Eigen::Vector2d origin(side.outer[2], side.outer[3]);
  // From here on the fitted edge's own normal: the corners the side was
  // taken from are a few tenths of a pixel off, which turns the normal by
  // a few milliradians, and 60 px along the side that is 0.1 px across.
  const Eigen::Vector2d fitted(-side.outer[1], side.outer[0]);
  side.normal = fitted.dot(side.normal) > 0 ? fitted : -fitted;
  double sum = 0.0;
  for (const cv::Point2f& q : points) {
    const double off = (Eigen::Vector2d(q.x, q.y) - origin).dot(side.normal);
    sum += off * off;
  }
  side.rms_px = std::sqrt(sum / points.size());

  // The inner edge along the middle fifth of each data cell, 0.4 of a cell
  // from its neighbours (under a phone's 2 px sharpening a black neighbour
  // still darkens the halo 5 px away): a black cell has no edge there and
  // fails EdgePoint's contrast test.
  std::vector<Eigen::Vector2d> widths;  // (t, width)
  widths.reserve((kTagCellsAcross - 2) *
                 (static_cast<size_t>(0.2 * cell / spacing) + 2));
  for (int k = 1; k < kTagCellsAcross - 1; ++k) {
    for (double t = (k + 0.4) * cell; t <= (k + 0.6) * cell; t += spacing) {
      const Eigen::Vector2d p = a + t * along - cell * side.normal;
      const auto edge = EdgePoint<T>(gray, region, p, -side.normal, &profile);
      if (!edge) continue;
      const double width = (origin - edge->point).dot(side.normal);
      if (std::abs(width - cell) < 0.25 * cell) {
        widths.emplace_back(t, width);
        whites.AddInner(k, edge->white);
      }
    }
  }
  if (widths.size() < 4) return side;
  // A gain on the light that changes across the border moves both of its
  // edges the same way, which the midline does not undo: shift the outer
  // edge back by it (the width, measured between the two, keeps).
  // The whites' centres lie cell + 2 (d - 1/2) apart across the border.
  if (const auto log_ratio = whites.LogRatio()) {
    side.white_log_ratio = *log_ratio;
    const double slope = *log_ratio / (cell + 2.0 * profile.d - 1.0);
    const double shift = EdgeShiftFromGainSlope(slope, profile.d);
    side.outer[2] -= static_cast<float>(shift * side.normal.x());
    side.outer[3] -= static_cast<float>(shift * side.normal.y());
  }
  FitWidthLine(widths, cell, &side);
  return side;
}

std::optional<BorderSide> FitBorderSide(const cv::Mat& gray,
                                        const LinearRegion& region,
                                        const Eigen::Vector2d& a,
                                        const Eigen::Vector2d& b,
                                        const TagDetectorOptions& options) {
  return WithLumaType(gray, [&](auto type) {
    return FitBorderSideOf<decltype(type)>(gray, region, a, b, options);
  });
}

Eigen::Vector2d Intersect(const Eigen::Vector2d& p1, const Eigen::Vector2d& d1,
                          const Eigen::Vector2d& p2,
                          const Eigen::Vector2d& d2) {
  // Points p1 + s d1 = p2 + t d2.
  Eigen::Matrix2d m;
  m << d1, -d2;
  const Eigen::Vector2d st = m.inverse() * (p2 - p1);
  return p1 + st[0] * d1;
}

// The outer corners from the border's midlines (FitBorderSideOf): the
// midlines meet at the corners of a square 7 cells across, and the plane's
// homography through them gives the black border's corners 8 cells across.
// A side whose six data cells are all black takes the other sides' mean
// width. Without any width (no white data cell on the border, or a tag too
// small to show one) the outer edges are used as they are.
std::array<Eigen::Vector2d, 4> CornersOf(
    const std::array<BorderSide, 4>& sides,
    const std::array<Eigen::Vector2d, 4>& approximate) {
  double width_sum = 0.0;
  int widths = 0;
  for (const BorderSide& side : sides) {
    if (side.has_width) width_sum += side.width_at_a, ++widths;
  }
  std::array<Eigen::Vector2d, 4> points, directions;
  for (int c = 0; c < 4; ++c) {
    const BorderSide& side = sides[c];
    const Eigen::Vector2d origin(side.outer[2], side.outer[3]);
    const Eigen::Vector2d direction(side.outer[0], side.outer[1]);
    if (widths == 0) {
      points[c] = origin, directions[c] = direction;
      continue;
    }
    // Two points of the midline, half the width inside the outer edge, at
    // the side's two ends.
    const Eigen::Vector2d& a = approximate[c];
    const Eigen::Vector2d& b = approximate[(c + 1) % 4];
    const double length = (b - a).norm();
    const auto on_outer = [&](const Eigen::Vector2d& p) {
      return origin + (p - origin).dot(direction) * direction;
    };
    const double w_a = side.has_width ? side.width_at_a : width_sum / widths;
    const double w_b = w_a + (side.has_width ? side.width_slope : 0.0) * length;
    const Eigen::Vector2d m_a = on_outer(a) - 0.5 * w_a * side.normal;
    const Eigen::Vector2d m_b = on_outer(b) - 0.5 * w_b * side.normal;
    points[c] = m_a, directions[c] = (m_b - m_a).normalized();
  }
  std::array<Eigen::Vector2d, 4> corners;
  for (int c = 0; c < 4; ++c) {
    corners[c] = Intersect(points[(c + 3) % 4], directions[(c + 3) % 4],
                           points[c], directions[c]);
  }
  if (widths == 0) return corners;
  // The square in cells about its centre: the midlines' corners are half a
  // cell inside the border's.
  const std::array<Eigen::Vector2d, 4> unit = {
      Eigen::Vector2d(-1, 1), Eigen::Vector2d(1, 1), Eigen::Vector2d(1, -1),
      Eigen::Vector2d(-1, -1)};
  std::array<Eigen::Vector2d, 4> midline_square;
  for (int c = 0; c < 4; ++c) {
    midline_square[c] = 0.5 * (kTagCellsAcross - 1) * unit[c];
  }
  const std::optional<Eigen::Matrix3d> image_from_cells =
      HomographyThrough(midline_square, corners);
  if (!image_from_cells) {  // no quadrilateral: the outer edges as found
    for (int c = 0; c < 4; ++c) {
      const cv::Vec4f& l1 = sides[(c + 3) % 4].outer;
      const cv::Vec4f& l2 = sides[c].outer;
      corners[c] = Intersect({l1[2], l1[3]}, {l1[0], l1[1]}, {l2[2], l2[3]},
                             {l2[0], l2[1]});
    }
    return corners;
  }
  for (int c = 0; c < 4; ++c) {
    corners[c] =
        (*image_from_cells * (0.5 * kTagCellsAcross * unit[c]).homogeneous())
            .hnormalized();
  }
  return corners;
}

// What the border fitted from `approximate` (its `sides`, and the `corners`
// CornersOf made of them) shows of the camera's processing; nullopt
// without a side's width.
std::optional<TagEdgeSigns> SignsOf(
    const std::array<BorderSide, 4>& sides,
    const std::array<Eigen::Vector2d, 4>& approximate,
    const std::array<Eigen::Vector2d, 4>& corners) {
  TagEdgeSigns signs;
  double shift_sum = 0.0, log_ratio_sum = 0.0;
  int widths = 0, ratios = 0;
  for (int c = 0; c < 4; ++c) {
    const BorderSide& side = sides[c];
    signs.halo += 0.25 * side.halo;
    if (side.white_log_ratio) log_ratio_sum += *side.white_log_ratio, ++ratios;
    if (!side.has_width) continue;
    // The width at the side's middle against the cell there (the final
    // corners' side over its 8 cells: perspective changes a cell along a
    // side by a few tenths of a percent, far under a sign worth naming).
    const double length = (approximate[(c + 1) % 4] - approximate[c]).norm();
    const double width = side.width_at_a + side.width_slope * length / 2.0;
    const double cell =
        (corners[(c + 1) % 4] - corners[c]).norm() / kTagCellsAcross;
    shift_sum += (width - cell) / 2.0;
    ++widths;
  }
  if (widths == 0) return std::nullopt;
  signs.edge_shift_px = shift_sum / widths;
  if (ratios > 0) signs.white_ratio = std::exp(log_ratio_sum / ratios) - 1.0;
  return signs;
}

// The four sides fitted from corners known to a few pixels; nullopt when a
// side's outer edge had too few clean points.
std::optional<std::array<BorderSide, 4>> FitBorder(
    const cv::Mat& gray, const std::array<Eigen::Vector2d, 4>& approximate,
    const TagDetectorOptions& options) {
  // One buffer per thread, reused for every fit (a tag is fitted in every
  // frame).
  thread_local cv::Mat buffer;
  const LinearRegion region =
      LinearRegionAround(gray, approximate, options.edge_half_width_px,
                         options.luma_encoding, &buffer);
  std::array<BorderSide, 4> sides;
  for (int c = 0; c < 4; ++c) {
    auto side = FitBorderSide(gray, region, approximate[c],
                              approximate[(c + 1) % 4], options);
    if (!side) return std::nullopt;
    sides[c] = *side;
  }
  return sides;
}

}  // namespace

std::optional<std::array<Eigen::Vector2d, 4>> RefineTagCorners(
    const cv::Mat& gray, const std::array<Eigen::Vector2d, 4>& approximate,
    const TagDetectorOptions& options, double max_edge_rms_px) {
  const auto sides = FitBorder(gray, approximate, options);
  if (!sides) return std::nullopt;
  for (const BorderSide& side : *sides) {
    // A covered or shadowed stretch leaves points out or bends the edge.
    if (side.clean < 0.9 * side.sampled || side.rms_px > max_edge_rms_px) {
      return std::nullopt;
    }
  }
  return CornersOf(*sides, approximate);
}

struct TagDetector::Apriltag {
  apriltag_family_t* family = tag36h11_create();
  apriltag_detector_t* detector = apriltag_detector_create();
  ~Apriltag() {
    apriltag_detector_destroy(detector);
    tag36h11_destroy(family);
  }
};

TagDetector::TagDetector(const TagDetectorOptions& options)
    : options_(options), apriltag_(std::make_unique<Apriltag>()) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  // Up to one corrected bit error: the two-bit table costs ~0.1 s to build,
  // and a tag big enough to measure by reads cleanly.
  apriltag_detector_add_family_bits(apriltag_->detector, apriltag_->family, 1);
  apriltag_->detector->quad_decimate = options.quad_decimate;
  apriltag_->detector->nthreads = 1;
}

TagDetector::~TagDetector() = default;

std::vector<TagDetection> TagDetector::Detect(const cv::Mat& gray) const {
  // libapriltag finds quads in 8 bits; the edges are fitted at full depth.
  const cv::Mat gray8 = LumaAs8Bit(gray, options_.luma_encoding);
  image_u8_t image{gray8.cols, gray8.rows, static_cast<int32_t>(gray8.step),
                   gray8.data};
  zarray_t* detections = apriltag_detector_detect(apriltag_->detector, &image);

  std::vector<TagDetection> tags;
  for (int i = 0; i < zarray_size(detections); ++i) {
    apriltag_detection_t* det = nullptr;
    zarray_get(detections, i, &det);
    TagDetection tag;
    tag.id = det->id;
    tag.hamming = det->hamming;
    for (int c = 0; c < 4; ++c) {
      // libapriltag puts pixel centres at +0.5; OpenCV at integers.
      tag.coarse_corners[c] = {det->p[c][0] - 0.5, det->p[c][1] - 0.5};
    }
    tag.corners = tag.coarse_corners;
    tag.refined = false;
    // Fitted again from the corners found until they hold still: the
    // profiles then sit centred on each edge, as a phone's sharpening halos
    // move an edge whose profile is off-centre by tenths of a pixel, and
    // libapriltag's corners can be a pixel off.
    for (int pass = 0; pass < kMaxBorderFits; ++pass) {
      const auto sides = FitBorder(gray, tag.corners, options_);
      if (!sides) break;
      const std::array<Eigen::Vector2d, 4> corners =
          CornersOf(*sides, tag.corners);
      const double moved = LargestCornerMove(corners, tag.corners);
      tag.signs = SignsOf(*sides, tag.corners, corners);
      tag.corners = corners;
      tag.refined = true;
      if (moved < 0.01) break;
    }
    tags.push_back(tag);
  }
  apriltag_detections_destroy(detections);
  return tags;
}

double LargestCornerMove(const std::array<Eigen::Vector2d, 4>& a,
                         const std::array<Eigen::Vector2d, 4>& b) {
  double largest = 0.0;
  for (int c = 0; c < 4; ++c) largest = std::max(largest, (a[c] - b[c]).norm());
  return largest;
}

std::array<Eigen::Vector2d, 4> AverageTagCorners(
    const std::array<Eigen::Vector2d, 4>& reference,
    const std::vector<std::array<Eigen::Vector2d, 4>>& frames) {
  SOFTBENCH_CHECK(!frames.empty()) << "no frames to average";
  const auto centroid = [](const std::array<Eigen::Vector2d, 4>& corners) {
    return 0.25 * (corners[0] + corners[1] + corners[2] + corners[3]);
  };
  const Eigen::Vector2d to = centroid(reference);
  std::array<Eigen::Vector2d, 4> sum;
  sum.fill(Eigen::Vector2d::Zero());
  for (const std::array<Eigen::Vector2d, 4>& corners : frames) {
    // The rotation best taking the frame's corners (about their centroid)
    // onto the reference's: atan2 of the summed cross and dot products.
    const Eigen::Vector2d from = centroid(corners);
    double cross = 0.0, dot = 0.0;
    for (int c = 0; c < 4; ++c) {
      const Eigen::Vector2d a = corners[c] - from, b = reference[c] - to;
      cross += a.x() * b.y() - a.y() * b.x();
      dot += a.dot(b);
    }
    const Eigen::Rotation2Dd roll(std::atan2(cross, dot));
    for (int c = 0; c < 4; ++c) sum[c] += to + roll * (corners[c] - from);
  }
  for (Eigen::Vector2d& corner : sum)
    corner /= static_cast<double>(frames.size());
  return sum;
}

std::optional<Eigen::Matrix3d> HomographyThrough(
    const std::array<Eigen::Vector2d, 4>& from,
    const std::array<Eigen::Vector2d, 4>& to) {
  Eigen::Matrix<double, 8, 8> a;
  Eigen::Matrix<double, 8, 1> b;
  for (int c = 0; c < 4; ++c) {
    const double x = from[c].x(), y = from[c].y();
    const double u = to[c].x(), v = to[c].y();
    a.row(2 * c) << x, y, 1, 0, 0, 0, -u * x, -u * y;
    a.row(2 * c + 1) << 0, 0, 0, x, y, 1, -v * x, -v * y;
    b(2 * c) = u, b(2 * c + 1) = v;
  }
  const Eigen::FullPivLU<Eigen::Matrix<double, 8, 8>> lu(a);
  if (!lu.isInvertible()) return std::nullopt;
  const Eigen::Matrix<double, 8, 1> h = lu.solve(b);
  Eigen::Matrix3d homography;
  homography << h(0), h(1), h(2), h(3), h(4), h(5), h(6), h(7), 1.0;
  return homography;
}

}  // namespace softbench
