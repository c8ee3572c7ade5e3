#include "pipelines/validation/validation.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "model/equilibrium.h"
#include "model/inverse.h"
#include "pipelines/validation/plan_consistency.h"
#include "pipelines/validation/uncertainty_budget.h"
#include "util/check.h"
#include "util/statistics.h"
#include "vision/plate_pose.h"

namespace softbench {
namespace {

// Equilibrium displacements of every head from rest for given pressures
// [MPa], solved from the rest state; NaN when the solver fails.
Eigen::VectorXd Predict(const EquilibriumProblem& problem,
                        const Eigen::VectorXd& pressures_mpa) {
  EquilibriumSolver solver(problem);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(problem.NumUnknowns());
  if (!solver.Solve(pressures_mpa, &x).converged()) {
    x.setConstant(NAN);
  }
  return x;
}

ErrorStatistics Statistics(const std::vector<double>& errors) {
  ErrorStatistics s;
  s.tests = static_cast<int>(errors.size());
  if (errors.empty()) return s;
  double sum = 0.0, squares = 0.0, largest = 0.0;
  for (double e : errors) {
    sum += e;
    squares += e * e;
    largest = std::max(largest, e);
  }
  s.mean_mm = sum / errors.size();
  s.rms_mm = std::sqrt(squares / errors.size());
  s.max_mm = largest;
  return s;
}

// What the tests flagged for hysteresis share, in words.
std::string SharedCause(const TestPlan& plan,
                        const std::vector<TestScore>& tests,
                        const std::vector<std::string>& flagged) {
  if (flagged.empty()) return "no test point exceeds the tolerance";
  std::vector<double> top;
  for (const TestScore& t : tests) top.push_back(t.pressures.maxCoeff());
  const double high = Quantile(top, 2.0 / 3.0);
  bool all_high = true, all_late = true;
  int common_actuator = -2;
  for (size_t i = 0; i < tests.size(); ++i) {
    if (std::find(flagged.begin(), flagged.end(), tests[i].id) ==
        flagged.end()) {
      continue;
    }
    all_high &= tests[i].pressures.maxCoeff() >= high;
    all_late &= 2 * i >= tests.size();
    int strongest = 0;
    tests[i].pressures.maxCoeff(&strongest);
    common_actuator =
        common_actuator == -2 || common_actuator == strongest ? strongest : -1;
  }
  std::vector<std::string> causes;
  if (flagged.size() >= 2 && all_high) {
    causes.push_back(fmt::format("all at high pressure (max >= {:g} {})", high,
                                 plan.pressure_unit));
  }
  if (flagged.size() >= 2 && all_late) {
    causes.emplace_back("all in the second half of the run (drift or creep?)");
  }
  if (flagged.size() >= 2 && common_actuator >= 0) {
    causes.push_back(fmt::format("all with actuator {} at the highest pressure",
                                 common_actuator + 1));
  }
  if (causes.empty()) {
    return flagged.size() == 1
               ? "one test point: " + flagged.front()
               : "no common cause in pressure level, actuator or time";
  }
  std::string text;
  for (const std::string& cause : causes) {
    text += (text.empty() ? "" : "; ") + cause;
  }
  return text;
}

// Names each window (once, however many tests share it) in which the
// camera moved, and says how far.
void WarnCameraMotion(const std::vector<TestScore>& tests,
                      const VideoMeasurement& measurement,
                      ValidationResult* result) {
  struct Moved {
    const WindowSummary* window;
    std::vector<std::string> names;
  };
  std::vector<Moved> moved;
  for (const TestScore& test : tests) {
    for (int k = 0; k < 3; ++k) {
      const WindowSummary& w = test.windows[k];
      if (!w.camera_moved) continue;
      const std::string name = test.id + " " + kWindowNames[k];
      auto same = std::find_if(moved.begin(), moved.end(), [&](const Moved& m) {
        return m.window->start_s == w.start_s && m.window->end_s == w.end_s;
      });
      if (same == moved.end()) {
        moved.push_back({&w, {name}});
      } else {
        same->names.push_back(name);
      }
    }
  }
  for (const Moved& m : moved) {
    const std::string names = fmt::format("{}", fmt::join(m.names, " = "));
    result->camera_moved_windows.push_back(names);
    result->warnings.push_back(fmt::format(
        "the camera moved {:.2f} px ({:.3f} mm at the dot plane) during "
        "window {} ({:.2f}-{:.2f} s); every frame is registered to the "
        "bench, so the positions are corrected, but steady the tripod",
        m.window->camera_motion_px,
        m.window->camera_motion_px * measurement.mm_per_px, names,
        m.window->start_s, m.window->end_s));
  }
}

// The number of independent samples that `series` (in time order) is worth:
// n (1 - r) / (1 + r) with r its lag-1 autocorrelation (an AR(1) series;
// negative r counted as none), at least 1.
double EffectiveSampleSize(const std::vector<double>& series) {
  const double n = static_cast<double>(series.size());
  if (series.size() < 3) return std::max(1.0, n);
  double mean = 0.0;
  for (double v : series) mean += v / n;
  double lag0 = 0.0, lag1 = 0.0;
  for (size_t i = 0; i < series.size(); ++i) {
    lag0 += (series[i] - mean) * (series[i] - mean);
    if (i > 0) lag1 += (series[i] - mean) * (series[i - 1] - mean);
  }
  const double r = lag0 > 0.0 ? std::clamp(lag1 / lag0, 0.0, 1.0) : 1.0;
  return std::max(1.0, n * (1.0 - r) / (1.0 + r));
}

}  // namespace

std::optional<std::string> ValidationOptions::Problem() const {
  if (!(recommended_hold_s >= 0.0)) return "recommended_hold_s must be >= 0";
  if (!(min_window_coverage > 0.0 && min_window_coverage <= 1.0)) {
    return "min_window_coverage must be in (0, 1]";
  }
  if (!(camera_motion_warning_px > 0.0)) {
    return "camera_motion_warning_px must be > 0";
  }
  if (!(mismatch_min_mm > 0.0) || !(mismatch_fraction > 0.0)) {
    return "mismatch_min_mm and mismatch_fraction must be > 0";
  }
  if (min_codec_jumps < 0) return "min_codec_jumps must be >= 0";
  if (!(better_match_ratio > 0.0 && better_match_ratio < 1.0) ||
      !(better_match_margin_mm >= 0.0)) {
    return "better_match_ratio must be in (0, 1), better_match_margin_mm >= 0";
  }
  return std::nullopt;
}

std::vector<std::array<WindowSummary, 3>> PlanWindows(const TestPlan& plan,
                                                      double video_end_s) {
  const double w = plan.window_s;
  std::vector<std::array<WindowSummary, 3>> windows(plan.tests.size());
  for (size_t i = 0; i < plan.tests.size(); ++i) {
    const TestPoint& test = plan.tests[i];
    // The rest ends at the next actuation, or where the video ends first
    // (a recording cut short), when a whole window still fits after the
    // release.
    double next =
        i + 1 < plan.tests.size() ? *plan.tests[i + 1].actuate_s : video_end_s;
    if (video_end_s < next && video_end_s - w >= *test.release_s) {
      next = video_end_s;
    }
    const std::array<double, 3> ends = {*test.actuate_s, *test.release_s, next};
    for (int k = 0; k < 3; ++k) {
      windows[i][k].start_s = ends[k] - w;
      windows[i][k].end_s = ends[k];
    }
  }
  return windows;
}

std::vector<double> WindowMiddles(
    const std::vector<std::array<WindowSummary, 3>>& windows) {
  std::vector<double> middles;
  for (const auto& test : windows) {
    for (const WindowSummary& w : test) middles.push_back(w.middle_s());
  }
  std::sort(middles.begin(), middles.end());
  middles.erase(std::unique(middles.begin(), middles.end()), middles.end());
  return middles;
}

namespace {

// A window's median of one quantity, the robust spread (1.4826 x median
// absolute deviation) and the median's standard error: 1.2533 x spread over
// the root of the frames' effective number (lag-1 correlation lowers it).
struct RobustMedian {
  double median, spread, standard_error;
};
RobustMedian MedianWithStandardError(const std::vector<double>& values) {
  RobustMedian out;
  out.median = Median(values);
  std::vector<double> deviations;
  for (double v : values) deviations.push_back(std::abs(v - out.median));
  out.spread = 1.4826 * Median(deviations);
  out.standard_error =
      std::sqrt(std::numbers::pi / 2.0 / EffectiveSampleSize(values)) *
      out.spread;
  return out;
}

}  // namespace

void SummariseWindow(const VideoMeasurement& measurement, int num_heads,
                     WindowSummary* window) {
  window->frames = 0;
  window->head_frames.assign(num_heads, 0);
  window->median_mm.assign(num_heads, Eigen::Vector2d::Constant(NAN));
  window->spread_mm.assign(num_heads, Eigen::Vector2d::Constant(NAN));
  window->standard_error_mm.assign(num_heads, Eigen::Vector2d::Constant(NAN));
  window->dot_median_mm.assign(num_heads, {});
  window->lift_mm.assign(num_heads, NAN);
  window->lift_standard_error_mm.assign(num_heads, NAN);
  window->parallax_mm.assign(num_heads, Eigen::Vector2d::Constant(NAN));
  std::vector<std::array<std::vector<double>, 2>> values(num_heads);
  // Per head: lift, and the parallax per axis.
  std::vector<std::array<std::vector<double>, 3>> lifts(num_heads);
  // Per head, dot and axis.
  std::vector<std::vector<std::array<std::vector<double>, 2>>> dots(num_heads);
  std::array<std::vector<double>, 2> camera;
  window->unregistered_frames = 0;
  window->damaged_frames = static_cast<int>(
      std::lower_bound(measurement.lost_frame_times_s.begin(),
                       measurement.lost_frame_times_s.end(), window->end_s) -
      std::lower_bound(measurement.lost_frame_times_s.begin(),
                       measurement.lost_frame_times_s.end(), window->start_s));
  // Frames are in time order: only the window's own are visited.
  const auto by_time = [](const FrameSample& frame, double time_s) {
    return frame.time_s < time_s;
  };
  const auto begin =
      std::lower_bound(measurement.frames.begin(), measurement.frames.end(),
                       window->start_s, by_time);
  const auto end =
      std::lower_bound(begin, measurement.frames.end(), window->end_s, by_time);
  for (auto it = begin; it != end; ++it) {
    const FrameSample& frame = *it;
    ++window->frames;
    if (frame.damaged) {
      ++window->damaged_frames;
    } else if (!frame.registered) {
      ++window->unregistered_frames;
    } else {
      camera[0].push_back(frame.camera_shift_px.x());
      camera[1].push_back(frame.camera_shift_px.y());
    }
    for (int h = 0; h < num_heads; ++h) {
      const HeadSample& head = frame.heads[h];
      if (!head.observation.complete) continue;
      ++window->head_frames[h];
      values[h][0].push_back(head.displacement_mm.x());
      values[h][1].push_back(head.displacement_mm.y());
      if (std::isfinite(head.lift_mm)) {
        lifts[h][0].push_back(head.lift_mm);
        lifts[h][1].push_back(head.parallax_mm.x());
        lifts[h][2].push_back(head.parallax_mm.y());
      }
      const std::vector<DotObservation>& found = head.observation.dots;
      dots[h].resize(found.size());
      for (size_t d = 0; d < found.size(); ++d) {
        dots[h][d][0].push_back(found[d].plane_mm.x());
        dots[h][d][1].push_back(found[d].plane_mm.y());
      }
    }
  }
  window->camera_motion_px = 0.0;
  if (!camera[0].empty()) {
    for (int a = 0; a < 2; ++a) {
      window->camera_shift_px[a] = Median(camera[a]);
      window->camera_motion_px =
          std::max(window->camera_motion_px,
                   Quantile(camera[a], 0.95) - Quantile(camera[a], 0.05));
    }
  }
  for (int h = 0; h < num_heads; ++h) {
    if (values[h][0].empty()) continue;
    for (int a = 0; a < 2; ++a) {
      const RobustMedian m = MedianWithStandardError(values[h][a]);
      window->median_mm[h][a] = m.median;
      window->spread_mm[h][a] = m.spread;
      window->standard_error_mm[h][a] = m.standard_error;
    }
    if (!lifts[h][0].empty()) {
      const RobustMedian lift = MedianWithStandardError(lifts[h][0]);
      window->lift_mm[h] = lift.median;
      window->lift_standard_error_mm[h] = lift.standard_error;
      window->parallax_mm[h] =
          Eigen::Vector2d(Median(lifts[h][1]), Median(lifts[h][2]));
    }
    for (const auto& dot : dots[h]) {
      window->dot_median_mm[h].emplace_back(Median(dot[0]), Median(dot[1]));
    }
  }
}

namespace {

// Why a window does not measure head `h`, or empty when it does: too few
// frames with the head complete, or no frames at all.
std::string WindowProblem(const TestPlan& plan,
                          const VideoMeasurement& measurement,
                          const ValidationOptions& options,
                          const WindowSummary& window, int k, int h) {
  if (window.frames > 0 &&
      window.head_frames[h] >= options.min_window_coverage * window.frames) {
    return "";
  }
  return fmt::format(
      "{} window {:.2f}-{:.2f} s: {}", kWindowNames[k], window.start_s,
      window.end_s,
      window.damaged_frames > 0
          ? fmt::format("{} frames lost to damaged video data",
                        window.damaged_frames)
      : window.start_s >= measurement.last_frame_s
          ? fmt::format("beyond the video's end ({:.2f} s); check the plan's "
                        "times",
                        measurement.last_frame_s)
      : window.frames == 0 ? "no frames"
      : 2 * window.unregistered_frames > window.frames
          ? fmt::format("{} of {} frames could not be registered to the "
                        "bench ({})",
                        window.unregistered_frames, window.frames,
                        measurement.unregistered_reason)
          : fmt::format("{} complete in {} of {} frames",
                        plan.mechanism.heads[h].name, window.head_frames[h],
                        window.frames));
}

// Summarises a test's three windows; the test is measured when every
// window measures every head.
void SummariseWindows(const TestPlan& plan, const VideoMeasurement& measurement,
                      const ValidationOptions& options, TestScore* score) {
  const int num_heads = plan.mechanism.NumHeads();
  score->measured = true;
  for (int k = 0; k < 3; ++k) {
    WindowSummary& window = score->windows[k];
    SummariseWindow(measurement, num_heads, &window);
    window.camera_moved =
        window.camera_motion_px > options.camera_motion_warning_px;
    for (int h = 0; h < num_heads; ++h) {
      std::string problem =
          WindowProblem(plan, measurement, options, window, k, h);
      if (problem.empty()) continue;
      if (score->measured) score->reason = std::move(problem);  // the first
      score->measured = false;
    }
  }
}

// Each head's measured displacement (actuated - initial) against the model
// and the baseline at the test's pressures, and its hysteresis (|final -
// initial|, thesis 4.1.3).
void ScoreHeads(const TestPlan& plan, const ForceModel& baseline,
                TestScore* score) {
  const Eigen::VectorXd pressures_mpa = score->pressures * plan.mpa_per_unit;
  const EquilibriumProblem problem(plan.mechanism, plan.force_model);
  const Eigen::VectorXd model = Predict(problem, pressures_mpa);
  score->outside_range =
      OutsideCharacterisedRange(plan.range, problem, pressures_mpa, model)
          .value_or("");
  const Eigen::VectorXd spring =
      Predict(EquilibriumProblem(plan.mechanism, baseline), pressures_mpa);
  score->predicted = model.allFinite() && spring.allFinite();
  if (model.allFinite()) {
    const ReachCheck reach =
        ReachOfPrediction(problem, plan.range, pressures_mpa, model);
    if (!reach.within) {
      score->beyond_reach =
          std::isfinite(reach.distance_mm)
              ? fmt::format(
                    "the model puts the heads {:.4g} mm beyond where "
                    "pressures up to the characterised {:.4g} {} "
                    "reach",
                    reach.distance_mm,
                    plan.range.max_pressure_mpa / plan.mpa_per_unit,
                    plan.pressure_unit)
              : fmt::format(
                    "the model's heads could not be shown to lie "
                    "where pressures up to the characterised {:.4g} "
                    "{} reach",
                    plan.range.max_pressure_mpa / plan.mpa_per_unit,
                    plan.pressure_unit);
    }
  }
  // A final window that starts less than half a window after the release
  // (a video that ends during the hold or just after it) sees the hold or a
  // head still moving back: its hysteresis is not judged.
  const double rest_s = score->windows[kFinalWindow].end_s -
                        score->windows[kActuatedWindow].end_s;
  const bool final_settled = rest_s >= 1.5 * plan.window_s;
  for (int h = 0; h < plan.mechanism.NumHeads(); ++h) {
    HeadScore& head = score->heads.emplace_back();
    head.model_mm = model.segment<2>(2 * h);
    head.baseline_mm = spring.segment<2>(2 * h);
    if (!score->measured) continue;
    const Eigen::Vector2d initial = score->windows[kInitialWindow].median_mm[h];
    head.measured_mm = score->windows[kActuatedWindow].median_mm[h] - initial;
    head.model_error_mm = (head.measured_mm - head.model_mm).norm();
    head.baseline_error_mm = (head.measured_mm - head.baseline_mm).norm();
    head.hysteresis_mm =
        (score->windows[kFinalWindow].median_mm[h] - initial).norm();
    head.hysteresis_judged = final_settled;
    head.hysteresis_ok = head.hysteresis_mm <= plan.hysteresis_tolerance_mm;
  }
  // "hysteresis" once the budgets show a head beyond the tolerance
  // (JudgeAgainstUncertainty).
  score->status = !score->measured    ? "not measured"
                  : !score->predicted ? "no prediction"
                                      : "ok";
  if (score->measured && !score->predicted) {
    score->reason = fmt::format(
        "the {} finds no equilibrium at these pressures, so there is "
        "nothing to score against; check the test's pressures and the "
        "constants",
        model.allFinite() ? "pressurized-spring baseline" : "model");
  } else if (score->measured && !final_settled) {
    score->reason = fmt::format(
        "hysteresis not judged: the final window ends {:.2f} s after the "
        "release, too soon for the head to have settled (the video ends)",
        rest_s);
  }
}

// A head's lift between its windows and the shift its parallax makes in
// the displacement; the lift's uncertainty from the two windows' standard
// errors, the codec's level in each (CodecLevel::lift_variance_mm2) and
// the dots' own errors in a change to each window (`lift_dots_mm`,
// LiftSigmaFromDots).
void AddLift(const std::array<WindowSummary, 3>& windows, int h,
             const CodecLevel& codec, const std::array<double, 3>& lift_dots_mm,
             HeadScore* head) {
  const WindowSummary& initial = windows[kInitialWindow];
  const auto change = [&](int k, double* lift, double* u) {
    *lift = windows[k].lift_mm[h] - initial.lift_mm[h];
    *u = std::hypot(std::hypot(initial.lift_standard_error_mm[h],
                               windows[k].lift_standard_error_mm[h],
                               std::sqrt(2.0 * codec.lift_variance_mm2)),
                    lift_dots_mm[k]);
  };
  change(kActuatedWindow, &head->lift_mm, &head->u_lift_mm);
  change(kFinalWindow, &head->final_lift_mm, &head->u_final_lift_mm);
  head->lift_shift_mm =
      (windows[kActuatedWindow].parallax_mm[h] - initial.parallax_mm[h]).norm();
}

// Each measured head's budgets: what the video shows of the codec and of
// the dots' disagreement, then each change's own terms.
// Returns how many jumps at I pictures the codec's term rests on.
int AddBudgets(const TestPlan& plan, const VideoMeasurement& measurement,
               std::vector<TestScore>* tests) {
  const CodecLevel codec = MeasureCodecLevel(measurement);
  const CameraAbovePlane camera = measurement.mapping
                                      ? measurement.mapping->CameraAbove()
                                      : CameraAbovePlane{};
  std::vector<const WindowSummary*> windows;
  for (const TestScore& t : *tests) {
    if (!t.measured) continue;
    windows.push_back(&t.windows[kInitialWindow]);
    windows.push_back(&t.windows[kActuatedWindow]);
  }
  for (int h = 0; h < plan.mechanism.NumHeads(); ++h) {
    HeadUncertaintyContext context;
    context.codec_jumps = codec.jumps;
    context.codec_level_mm2 = codec.variance_mm2;
    context.scale_relative =
        LayoutScaleUncertainty(windows, h, plan.markers[h].layout_mm);
    context.intrinsics = &measurement.intrinsics_sensitivity;
    context.parallax_in_positions = !measurement.lift_corrected;
    if (static_cast<size_t>(h) < measurement.rest_mm.size()) {
      context.rest_mm = measurement.rest_mm[h];
    }
    // The dots' disagreement is pooled over the actuated changes and over
    // the final ones apart: a dot's error under a phone's sharpening
    // follows where its edge falls on the pixel grid, so it changes with a
    // head that moved to its actuated place and mostly repeats in a head
    // back at rest, and one sigma of both would understate the first.
    std::array<HeadUncertaintyContext, 3> contexts;
    std::array<double, 3> lift_dots_mm = {0.0, 0.0, 0.0};
    for (int k : {kActuatedWindow, kFinalWindow}) {
      HeadUncertaintyContext& c = contexts[k];
      c = context;
      double squares = 0.0;
      for (const TestScore& t : *tests) {
        if (!t.measured) continue;
        const SimilarityResidual r =
            DotsSimilarityResidual(t.windows[kInitialWindow], t.windows[k], h);
        squares += r.sum_of_squares_mm2;
        c.dot_dof += r.dof;
      }
      if (c.dot_dof == 0) continue;
      c.dot_sigma_mm = std::sqrt(squares / c.dot_dof);
      // In the lift too, which is read from the dots' spacing: a few
      // hundredths of a pixel per dot are tenths of a millimetre of lift.
      if (camera.Found() &&
          static_cast<size_t>(h) < measurement.rest_dots_mm.size() &&
          measurement.rest_dots_mm[h].size() >= 2) {
        lift_dots_mm[k] = LiftSigmaFromDots(
            measurement.rest_dots_mm[h], camera, c.dot_sigma_mm,
            measurement.plate_dot_sigma_mm, measurement.plate_pose);
      }
    }
    for (TestScore& t : *tests) {
      if (!t.measured) continue;
      HeadScore& head = t.heads[h];
      head.budget =
          ChangeBudget(t.windows[kInitialWindow], t.windows[kActuatedWindow], h,
                       contexts[kActuatedWindow]);
      head.hysteresis_budget =
          ChangeBudget(t.windows[kInitialWindow], t.windows[kFinalWindow], h,
                       contexts[kFinalWindow]);
      AddLift(t.windows, h, codec, lift_dots_mm, &head);
    }
  }
  return codec.jumps;
}

// Each measured head's model error and hysteresis against the expanded
// uncertainty U = 2u of the change behind it; a test with a head whose
// hysteresis exceeds the tolerance by more than U is "hysteresis".
void JudgeAgainstUncertainty(double tolerance_mm, TestScore* t) {
  if (!t->measured) return;
  bool exceeds = false;
  for (HeadScore& head : t->heads) {
    head.model_error_significant =
        head.model_error_mm > 2.0 * head.budget.TotalMm();
    if (!head.hysteresis_judged) continue;
    const double expanded = 2.0 * head.hysteresis_budget.TotalMm();
    head.hysteresis_verdict =
        head.hysteresis_mm - tolerance_mm >= expanded   ? kHysteresisExceeds
        : tolerance_mm - head.hysteresis_mm >= expanded ? kHysteresisWithin
                                                        : kHysteresisCannotTell;
    exceeds |= head.hysteresis_verdict == kHysteresisExceeds;
  }
  if (exceeds && t->status == "ok") t->status = "hysteresis";
}

// Per head, the error statistics of the model and the baseline over the
// measured tests, and the model's improvement on the baseline (figs. 4.9,
// 4.17).
void SummariseErrors(int num_heads, ValidationResult* result) {
  for (int h = 0; h < num_heads; ++h) {
    std::vector<double> model, baseline;
    for (const TestScore& t : result->tests) {
      if (!t.scored()) continue;
      model.push_back(t.heads[h].model_error_mm);
      baseline.push_back(t.heads[h].baseline_error_mm);
    }
    result->model_errors.push_back(Statistics(model));
    result->baseline_errors.push_back(Statistics(baseline));
    const double base = result->baseline_errors[h].mean_mm;
    result->improvement_percent.push_back(
        100.0 * (base - result->model_errors[h].mean_mm) / base);
  }
}

// The largest expanded uncertainty of a scored displacement, and how the
// judged hysteresis verdicts fall.
void SummariseUncertainty(ValidationResult* result) {
  for (const TestScore& t : result->tests) {
    if (!t.scored()) continue;
    for (const HeadScore& head : t.heads) {
      // fmax ignores the NaN the largest starts as.
      result->largest_expanded_mm =
          std::fmax(result->largest_expanded_mm, 2.0 * head.budget.TotalMm());
      if (head.hysteresis_verdict == kHysteresisExceeds) {
        ++result->hysteresis_exceeds;
      } else if (head.hysteresis_verdict == kHysteresisWithin) {
        ++result->hysteresis_within;
      } else if (head.hysteresis_verdict == kHysteresisCannotTell) {
        ++result->hysteresis_cannot_tell;
      }
    }
  }
}

// Repeats: tests with the same pressures, and how far apart their measured
// displacements are, per head.
std::vector<RepeatAgreement> Repeats(const std::vector<TestScore>& tests,
                                     int num_heads) {
  std::vector<RepeatAgreement> repeats;
  std::vector<bool> grouped(tests.size(), false);
  for (size_t i = 0; i < tests.size(); ++i) {
    if (grouped[i]) continue;
    RepeatAgreement group;
    std::vector<size_t> members;
    for (size_t j = i; j < tests.size(); ++j) {
      if (!grouped[j] &&
          tests[j].pressures.isApprox(tests[i].pressures, 1e-12)) {
        grouped[j] = true;
        members.push_back(j);
        group.test_ids.push_back(tests[j].id);
      }
    }
    if (members.size() < 2) continue;
    for (int h = 0; h < num_heads; ++h) {
      double largest = 0.0;
      for (size_t a : members) {
        for (size_t b : members) {
          if (!tests[a].scored() || !tests[b].scored()) continue;
          const double d =
              (tests[a].heads[h].measured_mm - tests[b].heads[h].measured_mm)
                  .norm();
          if (std::isfinite(d)) largest = std::max(largest, d);
        }
      }
      group.max_difference_mm.push_back(largest);
    }
    repeats.push_back(group);
  }
  return repeats;
}

// Holds shorter than the thesis's settling time, and final windows too close
// to the release, are warned about.
void WarnAboutTiming(const TestPlan& plan, const ValidationOptions& options,
                     ValidationResult* result) {
  double shortest_hold_s = INFINITY;
  for (const TestPoint& test : plan.tests) {
    shortest_hold_s =
        std::min(shortest_hold_s, *test.release_s - *test.actuate_s);
  }
  if (shortest_hold_s < options.recommended_hold_s) {
    result->warnings.push_back(fmt::format(
        "holds as short as {:.1f} s: the thesis waited {:.0f} s after "
        "actuation for viscous creep to settle, so the actuated windows may "
        "not be at equilibrium",
        shortest_hold_s, options.recommended_hold_s));
  }
}

void WarnAboutSettling(const TestPlan& plan, ValidationResult* result) {
  for (const TestScore& score : result->tests) {
    if (!score.measured) continue;  // named with its reason already
    const double rest_s = score.windows[kFinalWindow].end_s -
                          score.windows[kActuatedWindow].end_s;
    if (rest_s < 2.0 * plan.window_s) {
      result->warnings.push_back(fmt::format(
          "{}: only {:.1f} s between release and the final window's end; the "
          "head may not have settled",
          score.id, rest_s));
    }
  }
}

// A head whose lift toward the camera is beyond 3u (a flat head's lift
// lies beyond its U = 2u one time in twenty, too often for a warning) and
// whose parallax moves its displacement by more than kLiftShiftWarnMm:
// named, with what was done about it. Not without the codec's term (fewer
// than min_codec_jumps jumps, as with --windows-only): a window's lift
// carries the codec's error in the dots' spacing, about 0.1 mm at 1080p,
// which its scatter does not show.
void WarnAboutLift(const TestPlan& plan, const VideoMeasurement& measurement,
                   int codec_jumps, const ValidationOptions& options,
                   ValidationResult* result) {
  constexpr double kLiftShiftWarnMm = 0.002;
  if (codec_jumps < options.min_codec_jumps) return;
  for (const TestScore& t : result->tests) {
    if (!t.measured) continue;
    for (size_t h = 0; h < t.heads.size(); ++h) {
      const HeadScore& s = t.heads[h];
      if (!(std::abs(s.lift_mm) > 3.0 * s.u_lift_mm &&
            s.lift_shift_mm > kLiftShiftWarnMm)) {
        continue;
      }
      result->warnings.push_back(fmt::format(
          "{}: head '{}' moved {:+.3f} mm (u {:.3f} mm) toward the camera, "
          "whose parallax moves its displacement by {:.4f} mm; {}",
          t.id, plan.mechanism.heads[h].name, s.lift_mm, s.u_lift_mm,
          s.lift_shift_mm,
          measurement.lift_corrected
              ? "taken out"
              : "left in, and counted in its uncertainty: "
                "--lift-correction takes it out, at the cost of the lift's "
                "noise (docs/measurement.md)"));
    }
  }
}

// A codec term measured on too few jumps at I pictures, or not at all.
void WarnAboutCodecTerm(int jumps, const VideoMeasurement& measurement,
                        const ValidationOptions& options,
                        ValidationResult* result) {
  if (jumps < options.min_codec_jumps) {
    result->warnings.push_back(fmt::format(
        "the uncertainties' codec term rests on {} jumps of a still head at "
        "an I picture, fewer than {}, so u may be too small (a codec "
        "repeats a still head's errors from one I picture to the next; "
        "docs/uncertainty.md){}",
        jumps, options.min_codec_jumps,
        measurement.every_frame
            ? ""
            : "; only the windows were read: validate without "
              "--windows-only for a budget that holds"));
  }
}

// Frames lost to damaged video data, in the video and per window.
void WarnAboutDamage(const VideoMeasurement& measurement,
                     ValidationResult* result) {
  const int lost = measurement.damaged_frames +
                   static_cast<int>(measurement.lost_frame_times_s.size());
  if (lost == 0) return;
  result->warnings.push_back(fmt::format(
      "{} frames lost to damaged video data ({} decoded with errors, {} "
      "never decoded); re-copy or re-export the video",
      lost, measurement.damaged_frames, measurement.lost_frame_times_s.size()));
  for (const TestScore& t : result->tests) {
    for (int k = 0; k < 3; ++k) {
      if (t.windows[k].damaged_frames > 0) {
        result->warnings.push_back(fmt::format(
            "{} {} window: {} of its frames lost to damaged video data{}", t.id,
            kWindowNames[k], t.windows[k].damaged_frames,
            t.measured ? " (measured from the others)" : ""));
      }
    }
  }
}

}  // namespace

ValidationResult ScoreTests(const TestPlan& plan,
                            const VideoMeasurement& measurement,
                            const ValidationOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  SOFTBENCH_CHECK(plan.HasTimes()) << "ScoreTests needs the plan's times";
  const int num_heads = plan.mechanism.NumHeads();
  ValidationResult result;
  result.model_name =
      "axial-shear (" + std::string(VariantName(plan.force_model)) + ")";
  result.baseline_name = "pressurized-spring";
  const ForceModel baseline =
      ForceModel::PressurizedSpring(plan.force_model.constants);
  const std::vector<std::array<WindowSummary, 3>> windows =
      PlanWindows(plan, measurement.last_frame_s);
  for (size_t i = 0; i < plan.tests.size(); ++i) {
    TestScore& score = result.tests.emplace_back();
    score.id = plan.tests[i].id;
    score.pressures = plan.tests[i].pressures;
    score.windows = windows[i];
    SummariseWindows(plan, measurement, options, &score);
    ScoreHeads(plan, baseline, &score);
  }
  const int codec_jumps = AddBudgets(plan, measurement, &result.tests);
  result.codec_jumps = codec_jumps;
  for (TestScore& t : result.tests) {
    JudgeAgainstUncertainty(plan.hysteresis_tolerance_mm, &t);
  }
  result.warnings = CheckPlanConsistency(options, &result.tests);
  const EquilibriumProblem problem(plan.mechanism, plan.force_model);
  if (std::optional<std::string> unit = PressureUnitThatFits(
          options, result.tests, plan.pressure_unit,
          [&](const Eigen::VectorXd& mpa) { return Predict(problem, mpa); })) {
    result.warnings.push_back(*unit);
  }
  for (const TestScore& score : result.tests) {
    if (!score.matches_plan) result.mismatched.push_back(score.id);
    if (score.status == "hysteresis") {
      result.hysteresis_flagged.push_back(score.id);
    }
  }
  SummariseErrors(num_heads, &result);
  SummariseUncertainty(&result);
  result.repeats = Repeats(result.tests, num_heads);
  result.hysteresis_cause =
      SharedCause(plan, result.tests, result.hysteresis_flagged);
  WarnAboutTiming(plan, options, &result);
  WarnCameraMotion(result.tests, measurement, &result);
  WarnAboutDamage(measurement, &result);
  WarnAboutSettling(plan, &result);
  WarnAboutCodecTerm(codec_jumps, measurement, options, &result);
  WarnAboutLift(plan, measurement, codec_jumps, options, &result);
  for (const TestScore& score : result.tests) {
    if (!score.beyond_reach.empty()) {
      result.warnings.push_back(fmt::format(
          "{}: {}; the bench cannot show this prediction, and its error "
          "says nothing about the constants",
          score.id, score.beyond_reach));
    }
    if (!score.outside_range.empty()) {
      result.warnings.push_back(
          fmt::format("{}: the model extrapolates here ({}); its error says "
                      "little about the constants",
                      score.id, score.outside_range));
    }
  }
  return result;
}

}  // namespace softbench
