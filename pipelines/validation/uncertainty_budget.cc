#include "pipelines/validation/uncertainty_budget.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <optional>

#include "pipelines/measurement/video_measurement.h"
#include "pipelines/validation/validation.h"
#include "util/statistics.h"
#include "vision/layout_scale.h"

namespace softbench {

std::string UncertaintyBudget::Largest() const {
  std::string name;
  double largest = -1.0;
  for (const UncertaintyTerm& term : terms) {
    if (term.u_mm.squaredNorm() > largest) {
      largest = term.u_mm.squaredNorm();
      name = term.name;
    }
  }
  return name;
}

SimilarityResidual DotsSimilarityResidual(const WindowSummary& from,
                                          const WindowSummary& to, int h) {
  return DotsSimilarityResidual(from.dot_median_mm[h], to.dot_median_mm[h]);
}

SimilarityResidual DotsSimilarityResidual(
    const std::vector<Eigen::Vector2d>& a,
    const std::vector<Eigen::Vector2d>& b) {
  const int n = static_cast<int>(a.size());
  if (n < 3 || b.size() != a.size()) return {};
  Eigen::Vector2d centre = Eigen::Vector2d::Zero(),
                  shift = Eigen::Vector2d::Zero();
  for (int d = 0; d < n; ++d) {
    centre += a[d] / n;
    shift += (b[d] - a[d]) / n;
  }
  // A small turn w moves a dot at offset r by w (-r.y, r.x), and a change
  // of scale s by s r: a head's lift h toward the camera at height H scales
  // its dots by h / (H - h), which is the head's motion, not the dots'
  // error. The shift's, turn's and scale's directions are orthogonal over
  // the dots, so each is fitted on its own.
  double turn_num = 0.0, scale_num = 0.0, den = 0.0;
  for (int d = 0; d < n; ++d) {
    const Eigen::Vector2d r = a[d] - centre;
    const Eigen::Vector2d perp(-r.y(), r.x());
    const Eigen::Vector2d change = b[d] - a[d] - shift;
    turn_num += perp.dot(change);
    scale_num += r.dot(change);
    den += r.squaredNorm();
  }
  const double turn = den > 0.0 ? turn_num / den : 0.0;
  const double scale = den > 0.0 ? scale_num / den : 0.0;
  SimilarityResidual residual;
  for (int d = 0; d < n; ++d) {
    const Eigen::Vector2d r = a[d] - centre;
    const Eigen::Vector2d perp(-r.y(), r.x());
    residual.sum_of_squares_mm2 +=
        (b[d] - a[d] - shift - turn * perp - scale * r).squaredNorm();
  }
  residual.dof = 2 * n - 4;
  return residual;
}

namespace {

// Whether frame `f` measured head `h`: registered, undamaged, every dot.
bool MeasuresHead(const FrameSample& f, int h) {
  return f.registered && !f.damaged && f.heads[h].observation.complete;
}

}  // namespace

double StillRangeMm(const VideoMeasurement& measurement, int h) {
  constexpr double kScatters = 6.0;
  const std::vector<FrameSample>& frames = measurement.frames;
  std::array<std::vector<double>, 2> second;
  for (size_t i = 2; i < frames.size(); ++i) {
    if (!MeasuresHead(frames[i], h) || !MeasuresHead(frames[i - 1], h) ||
        !MeasuresHead(frames[i - 2], h) ||
        frames[i].frame != frames[i - 2].frame + 2) {
      continue;
    }
    const Eigen::Vector2d d = frames[i].heads[h].displacement_mm -
                              2.0 * frames[i - 1].heads[h].displacement_mm +
                              frames[i - 2].heads[h].displacement_mm;
    for (int a = 0; a < 2; ++a) second[a].push_back(std::abs(d[a]));
  }
  double scatter_mm = 0.0;
  for (const std::vector<double>& values : second) {
    if (values.empty()) continue;
    scatter_mm = std::max(scatter_mm, 1.4826 * Median(values) / std::sqrt(6.0));
  }
  return std::max(kStillPx * measurement.mm_per_px, kScatters * scatter_mm);
}

std::vector<IntraJump> StillIntraJumps(const VideoMeasurement& measurement,
                                       int h) {
  constexpr int kMinSide = 3, kMaxSide = 8;
  // A jump beyond 10 kStillPx is a head that stepped between two frames:
  // the codec's levels are hundredths of a pixel, however the frames
  // scatter about them.
  constexpr double kMaxJumpPx = 10.0 * kStillPx;
  const std::vector<FrameSample>& frames = measurement.frames;
  const double still_mm = StillRangeMm(measurement, h);
  const int n = static_cast<int>(frames.size());
  // The head's positions on one side: frames i, i + step, ... while they
  // follow each other in the video, measure the head and are no other I
  // picture (after the first).
  const auto side = [&](int i, int step) {
    // y, z and the lift (NaN without one).
    std::array<std::vector<double>, 3> values;
    for (int j = i; j >= 0 && j < n && std::abs(j - i) < kMaxSide; j += step) {
      const FrameSample& f = frames[j];
      if (f.frame != frames[i].frame + (j - i) || (j != i && f.intra) ||
          !MeasuresHead(f, h)) {
        break;
      }
      values[0].push_back(f.heads[h].displacement_mm.x());
      values[1].push_back(f.heads[h].displacement_mm.y());
      values[2].push_back(f.heads[h].lift_mm);
    }
    return values;
  };
  const auto still = [&](const std::array<std::vector<double>, 3>& values) {
    if (values[0].size() < static_cast<size_t>(kMinSide)) return false;
    for (int a = 0; a < 2; ++a) {
      const auto [low, high] =
          std::minmax_element(values[a].begin(), values[a].end());
      if (*high - *low > still_mm) return false;
    }
    return true;
  };
  std::vector<IntraJump> jumps;
  for (int i = 1; i < n; ++i) {
    if (!frames[i].intra) continue;
    const auto after = side(i, 1);
    const auto before = side(i - 1, -1);
    if (frames[i - 1].frame + 1 != frames[i].frame || frames[i - 1].intra ||
        !still(after) || !still(before)) {
      continue;
    }
    IntraJump jump;
    jump.position_mm = Eigen::Vector2d(Median(after[0]) - Median(before[0]),
                                       Median(after[1]) - Median(before[1]));
    // A head that stepped between two frames, not the codec.
    if (jump.position_mm.cwiseAbs().maxCoeff() >
        kMaxJumpPx * measurement.mm_per_px) {
      continue;
    }
    const auto finite = [](const std::vector<double>& v) {
      return std::all_of(v.begin(), v.end(),
                         [](double x) { return std::isfinite(x); });
    };
    if (finite(after[2]) && finite(before[2])) {
      jump.lift_mm = Median(after[2]) - Median(before[2]);
    }
    jumps.push_back(jump);
  }
  return jumps;
}

CodecLevel MeasureCodecLevel(const VideoMeasurement& measurement) {
  CodecLevel codec;
  const size_t num_heads =
      measurement.frames.empty() ? 0 : measurement.frames[0].heads.size();
  Eigen::Vector2d squares = Eigen::Vector2d::Zero();
  double lift_squares = 0.0;
  int lift_jumps = 0;
  for (size_t h = 0; h < num_heads; ++h) {
    for (const IntraJump& jump :
         StillIntraJumps(measurement, static_cast<int>(h))) {
      squares += jump.position_mm.array().square().matrix();
      ++codec.jumps;
      if (std::isfinite(jump.lift_mm)) {
        lift_squares += jump.lift_mm * jump.lift_mm;
        ++lift_jumps;
      }
    }
  }
  if (codec.jumps > 0) codec.variance_mm2 = 0.5 * squares / codec.jumps;
  if (lift_jumps > 0) codec.lift_variance_mm2 = 0.5 * lift_squares / lift_jumps;
  return codec;
}

Eigen::Vector2d FrameUncertaintyMm(const VideoMeasurement& measurement,
                                   const CodecLevel& codec, int h) {
  const std::vector<FrameSample>& frames = measurement.frames;
  // The frame's level and the rest's.
  Eigen::Vector2d variance = 2.0 * codec.variance_mm2;
  // Steps between consecutive frames of a still head.
  const double still_mm = StillRangeMm(measurement, h);
  Eigen::Vector2d steps = Eigen::Vector2d::Zero();
  int num_steps = 0;
  std::optional<std::vector<Eigen::Vector2d>> first_dots;
  double dot_squares = 0.0;
  int dot_dof = 0;
  std::vector<Eigen::Vector2d> dots;
  for (size_t i = 0; i < frames.size(); ++i) {
    const FrameSample& f = frames[i];
    if (!MeasuresHead(f, h)) continue;
    if (i > 0 && !f.intra && MeasuresHead(frames[i - 1], h) &&
        frames[i - 1].frame + 1 == f.frame) {
      const Eigen::Vector2d step =
          f.heads[h].displacement_mm - frames[i - 1].heads[h].displacement_mm;
      if (step.cwiseAbs().maxCoeff() <= still_mm) {
        steps += step.array().square().matrix();
        ++num_steps;
      }
    }
    dots.clear();
    for (const DotObservation& d : f.heads[h].observation.dots) {
      dots.push_back(d.plane_mm);
    }
    if (!first_dots) {
      first_dots = dots;
      continue;
    }
    const SimilarityResidual r = DotsSimilarityResidual(*first_dots, dots);
    dot_squares += r.sum_of_squares_mm2;
    dot_dof += r.dof;
  }
  if (num_steps > 0) variance += 0.5 * steps / num_steps;
  if (dot_dof > 0 && !dots.empty()) {
    variance += Eigen::Vector2d::Constant(dot_squares / dot_dof / dots.size());
  }
  return variance.array().sqrt();
}

double LayoutScaleUncertainty(const std::vector<const WindowSummary*>& windows,
                              int h,
                              const std::vector<Eigen::Vector2d>& layout_mm) {
  const auto sum = [](const std::vector<double>& values) {
    return std::accumulate(values.begin(), values.end(), 0.0);
  };
  const double nominal = sum(PairDistances(layout_mm));
  std::vector<double> ratios;
  for (const WindowSummary* w : windows) {
    const std::vector<Eigen::Vector2d>& dots = w->dot_median_mm[h];
    if (dots.size() != layout_mm.size() || !(nominal > 0.0)) continue;
    ratios.push_back(sum(PairDistances(dots)) / nominal);
  }
  if (ratios.empty()) return 0.0;
  const double median = Median(ratios);
  std::vector<double> deviations;
  for (double r : ratios) deviations.push_back(std::abs(r - median));
  const double spread = 1.4826 * Median(deviations);
  return std::hypot(median - 1.0,
                    spread / std::sqrt(static_cast<double>(ratios.size())));
}

UncertaintyBudget ChangeBudget(const WindowSummary& from,
                               const WindowSummary& to, int h,
                               const HeadUncertaintyContext& context) {
  UncertaintyBudget budget;
  const Eigen::Vector2d scatter = (from.standard_error_mm[h].array().square() +
                                   to.standard_error_mm[h].array().square())
                                      .sqrt();
  budget.terms.push_back({"window scatter", scatter});
  const int dots = static_cast<int>(from.dot_median_mm[h].size());
  if (context.dot_dof > 0 && dots > 0) {
    budget.terms.push_back({"dots", Eigen::Vector2d::Constant(
                                        context.dot_sigma_mm /
                                        std::sqrt(static_cast<double>(dots)))});
  }
  if (context.codec_jumps > 0) {
    budget.terms.push_back(
        {"codec", (2.0 * context.codec_level_mm2).array().sqrt()});
  }
  if (context.scale_relative > 0.0) {
    const double length = (to.median_mm[h] - from.median_mm[h]).norm();
    budget.terms.push_back(
        {"scale", Eigen::Vector2d::Constant(context.scale_relative * length)});
  }
  if (context.intrinsics != nullptr && context.intrinsics->Known()) {
    budget.terms.push_back(
        {"intrinsics", context.intrinsics->ChangeUncertaintyMm(
                           context.rest_mm + from.median_mm[h],
                           context.rest_mm + to.median_mm[h])});
  }
  if (context.parallax_in_positions) {
    // NaN where either window has no lift: no term.
    const Eigen::Vector2d parallax = to.parallax_mm[h] - from.parallax_mm[h];
    if (parallax.allFinite()) {
      budget.terms.push_back({"parallax", parallax.cwiseAbs()});
    }
  }
  Eigen::Vector2d variance = Eigen::Vector2d::Zero();
  for (const UncertaintyTerm& term : budget.terms) {
    variance += term.u_mm.array().square().matrix();
  }
  budget.u_mm = variance.array().sqrt();
  return budget;
}

}  // namespace softbench
