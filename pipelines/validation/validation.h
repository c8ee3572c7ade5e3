#ifndef SOFTBENCH_PIPELINES_VALIDATION_VALIDATION_H_
#define SOFTBENCH_PIPELINES_VALIDATION_VALIDATION_H_

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "model/actuator_model.h"
#include "pipelines/formats/test_plan.h"
#include "pipelines/measurement/video_measurement.h"
#include "pipelines/validation/uncertainty_budget.h"

namespace softbench {

// The three frames of the thesis's method (4.1.3), each a window of frames.
enum WindowKind { kInitialWindow = 0, kActuatedWindow = 1, kFinalWindow = 2 };
inline constexpr std::array<const char*, 3> kWindowNames = {
    "initial", "actuated", "final"};

struct ValidationOptions {
  // Holds shorter than this are warned about: the thesis waited 20 s after
  // actuation for viscous creep to settle (4.1.3).
  double recommended_hold_s = 20.0;
  // A window needs the head complete (every dot found) in at least this
  // fraction of its frames to count as measured.
  double min_window_coverage = 0.5;
  // A window in which the camera moved further than this (its shift's 5-95 %
  // range, either axis) [px] is named in a warning: the registration
  // corrects it, but a tripod that moves during a window is worth fixing.
  // Tremor (< 0.1 px) and a slow drift stay below it; a bump does not.
  double camera_motion_warning_px = 0.5;
  // A test whose motion is further from its own entry's prediction than
  // both of these [mm] and [fraction of the predicted motion] does not match
  // its plan entry (plan_consistency.h): far above the model errors the
  // thesis reports (0.04 mm delta, 0.27 mm floating mean; 4.1.4, 4.2.4).
  double mismatch_min_mm = 0.5;
  double mismatch_fraction = 0.5;
  // Nor does a test that is within this fraction of its own prediction's
  // distance of another entry's prediction, and closer by this margin [mm]:
  // the signature of tests swapped or shifted against the plan.
  double better_match_ratio = 0.25;
  double better_match_margin_mm = 0.3;
  // Fewer jumps of a still head at I pictures than this leave the
  // uncertainty's codec term poorly measured (or missing), and are warned
  // about (uncertainty_budget.h). 10 jumps give its variance to about
  // +-45 % (95 %).
  int min_codec_jumps = 10;

  std::optional<std::string> Problem() const;
};

// A window's robust summary, per head.
struct WindowSummary {
  double start_s = 0.0;
  double end_s = 0.0;
  int frames = 0;                // frames in the window
  std::vector<int> head_frames;  // frames with the head complete
  // Median displacement from rest [mm] and the robust spread per axis
  // (1.4826 x median absolute deviation), NaN when not measured.
  std::vector<Eigen::Vector2d> median_mm;
  std::vector<Eigen::Vector2d> spread_mm;
  // The standard error of median_mm per axis [mm]: 1.2533 x spread over the
  // root of the frames' effective number, which the lag-1 correlation of
  // the frames' positions lowers (a still scene's codec repeats a frame's
  // errors for seconds); NaN when not measured.
  std::vector<Eigen::Vector2d> standard_error_mm;
  // Per head and dot, the dot's median plane position [mm] over the frames
  // with the head complete: the dots' disagreement is a term of the
  // uncertainty budget (uncertainty_budget.h).
  std::vector<std::vector<Eigen::Vector2d>> dot_median_mm;
  // Per head, the median lift toward the camera against the rest [mm]
  // (HeadSample::lift_mm) and its standard error as standard_error_mm's;
  // and the median parallax the lift and tilt add to the dots' centre [mm]
  // (what the correction takes out). NaN when not measured.
  std::vector<double> lift_mm;
  std::vector<double> lift_standard_error_mm;
  std::vector<Eigen::Vector2d> parallax_mm;
  // The camera during the window (registered frames): its median shift
  // since the reference frame and how far it moved within the window (the
  // larger axis's 5-95 % range) [px]; frames not registered to the bench.
  Eigen::Vector2d camera_shift_px = Eigen::Vector2d::Constant(NAN);
  double camera_motion_px = 0.0;
  bool camera_moved = false;  // above camera_motion_warning_px
  int unregistered_frames = 0;
  // Frames lost to damaged video data (decoded with errors, or never
  // decoded): the window is marked, never silently short.
  int damaged_frames = 0;

  // The frame the report shows for the window.
  double middle_s() const { return 0.5 * (start_s + end_s); }
};

// A hysteresis against the tolerance, given its expanded uncertainty U.
inline constexpr const char* kHysteresisExceeds = "exceeds tolerance";
inline constexpr const char* kHysteresisWithin = "within tolerance";
inline constexpr const char* kHysteresisCannotTell = "cannot tell";

struct HeadScore {
  Eigen::Vector2d measured_mm = Eigen::Vector2d::Constant(NAN);  // act - init
  Eigen::Vector2d model_mm = Eigen::Vector2d::Constant(NAN);
  Eigen::Vector2d baseline_mm = Eigen::Vector2d::Constant(NAN);
  double model_error_mm = NAN;  // |measured - model| (figs. 4.9, 4.17)
  double baseline_error_mm = NAN;
  double hysteresis_mm = NAN;  // |final - initial|
  bool hysteresis_ok = false;  // hysteresis_mm <= the tolerance
  // hysteresis_mm against the tolerance with U = 2u of its change: "exceeds
  // tolerance" (h - tolerance >= U), "within tolerance" (tolerance - h >=
  // U) or "cannot tell"; empty when not judged.
  std::string hysteresis_verdict;
  // False when the final window came too soon after the release for the
  // head to settle (a video that ends during the rest): hysteresis_mm is
  // then no evidence either way, and hysteresis_ok is not a verdict.
  bool hysteresis_judged = true;
  // The uncertainty of measured_mm and of the hysteresis's change (final -
  // initial), term by term (uncertainty_budget.h).
  UncertaintyBudget budget;
  UncertaintyBudget hysteresis_budget;
  // model_error_mm exceeds U = 2u of measured_mm: the error is the model's,
  // not the measurement's.
  bool model_error_significant = false;
  // The head's lift toward the camera (issue 27), actuated - initial and
  // final - initial [mm], with their standard uncertainties [mm]; NaN when
  // not measured.
  double lift_mm = NAN, u_lift_mm = NAN;
  double final_lift_mm = NAN, u_final_lift_mm = NAN;
  // How far the lift's and tilt's parallax moves measured_mm [mm]: taken
  // out of it when the measurement corrects lift, left in it when not.
  double lift_shift_mm = NAN;
};

struct TestScore {
  std::string id;
  Eigen::VectorXd pressures;  // in the plan's unit
  std::array<WindowSummary, 3> windows;
  std::vector<HeadScore> heads;
  bool measured = false;  // every window measured for every head
  // The motion fits the test's own plan entry (plan_consistency.h).
  bool matches_plan = true;
  // The model and the baseline both found an equilibrium at the test's
  // pressures: without one there is nothing to score against.
  bool predicted = true;
  // "ok", "hysteresis", "not measured", "mismatch", "no prediction"
  std::string status;
  // Why not measured, not scored, or why its hysteresis is not judged.
  std::string reason;
  // Why the model extrapolates at this test (beyond the constants'
  // characterised range), or empty.
  std::string outside_range;
  // Why the model's prediction lies beyond the mechanism's reach (no
  // pressures in the characterised range put the heads there), or empty.
  std::string beyond_reach;

  // Measured, matched to its plan entry and predicted: counted in the
  // statistics.
  bool scored() const { return measured && matches_plan && predicted; }
};

// Error statistics of one model for one head over the measured tests [mm].
struct ErrorStatistics {
  int tests = 0;
  double mean_mm = NAN;
  double max_mm = NAN;
  double rms_mm = NAN;
};

struct RepeatAgreement {
  std::vector<std::string> test_ids;  // tests with the same pressures
  // Largest distance between their measured displacements, per head [mm].
  std::vector<double> max_difference_mm;
};

struct ValidationResult {
  std::vector<TestScore> tests;
  std::string model_name;     // "axial-shear (small-angle)"
  std::string baseline_name;  // "pressurized-spring"
  // Per head.
  std::vector<ErrorStatistics> model_errors;
  std::vector<ErrorStatistics> baseline_errors;
  // (baseline mean - model mean) / baseline mean, in %, per head.
  std::vector<double> improvement_percent;
  std::vector<RepeatAgreement> repeats;
  std::vector<std::string> hysteresis_flagged;  // test ids
  std::vector<std::string> mismatched;          // test ids (plan_consistency.h)
  std::string hysteresis_cause;  // what the flagged tests share, if anything
  // Judged heads' hysteresis verdicts (HeadScore::hysteresis_verdict).
  int hysteresis_exceeds = 0;
  int hysteresis_within = 0;
  int hysteresis_cannot_tell = 0;
  // The largest U = 2u of a scored displacement [mm].
  double largest_expanded_mm = NAN;
  // The jumps of a still head at I pictures that the uncertainties' codec
  // term rests on (MeasureCodecLevel; too few: see min_codec_jumps).
  int codec_jumps = 0;
  std::vector<std::string> warnings;
  // The windows in which the camera moved (camera_motion_warning_px), each
  // once, as "b actuated" (a test's final window is the next one's
  // initial window: "a final = b initial").
  std::vector<std::string> camera_moved_windows;
  // Where the test points' times came from ("the plan", "the motion ...").
  std::string times_source = "the plan";
};

// The windows of each test from the plan's times: initial just before
// actuation, actuated at the end of the hold, final just before the next
// actuation (the video's end for the last test). Needs plan.HasTimes().
std::vector<std::array<WindowSummary, 3>> PlanWindows(const TestPlan& plan,
                                                      double video_end_s);

// The middles of all windows, sorted, each once (a test's final window is
// the next one's initial window).
std::vector<double> WindowMiddles(
    const std::vector<std::array<WindowSummary, 3>>& windows);

// Summarises the measured frames in a window.
void SummariseWindow(const VideoMeasurement& measurement, int num_heads,
                     WindowSummary* window);

// Scores every test of the plan against the model and the baseline (the
// plan's force model, and the pressurized spring with its A_z and k_s).
ValidationResult ScoreTests(const TestPlan& plan,
                            const VideoMeasurement& measurement,
                            const ValidationOptions& options);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_VALIDATION_VALIDATION_H_
