#include "pipelines/measurement/pressure_log.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

#include "pipelines/formats/pressure_csv.h"
#include "util/input_error.h"
#include "util/statistics.h"

namespace softbench {
namespace {

// How far a hold's logged length may be from the motion's (a regulator that
// is slow to vent stretches a hold, but not threefold).
constexpr double kMaxHoldDurationRatio = 3.0;

}  // namespace

std::vector<PressureHold> PressureLogHolds(
    const std::vector<double>& times_s,
    const std::vector<Eigen::VectorXd>& pressures, double tolerance) {
  std::vector<PressureHold> holds;
  bool open = false;
  for (size_t i = 0; i < pressures.size(); ++i) {
    const bool zero = pressures[i].cwiseAbs().maxCoeff() <= tolerance;
    const bool same =
        open && (pressures[i] - holds.back().pressures).cwiseAbs().maxCoeff() <=
                    tolerance;
    if (open && !same) {
      holds.back().end_s = times_s[i];
      open = false;
    }
    if (!open && !zero) {
      holds.push_back({times_s[i], times_s[i], pressures[i]});
      open = true;
    }
  }
  // A hold still open at the log's end lasts to its last row.
  if (open) holds.back().end_s = times_s.back();
  return holds;
}

std::vector<PressureHold> PlanPressureHolds(const TestPlan& plan,
                                            const std::string& path,
                                            DecimalMark decimal_mark) {
  PressureCsvOptions csv;
  csv.decimal_mark = decimal_mark;
  csv.num_actuators = plan.mechanism.NumActuators();
  csv.with_times = true;
  csv.stated_unit = plan.pressure_unit;  // columns in another unit convert
  const PressureRows log = ReadPressureRows(path, csv);
  std::vector<PressureHold> holds =
      PressureLogHolds(log.times_s, log.rows, 1e-6);
  if (holds.size() != plan.tests.size()) {
    throw InputError(fmt::format(
        "{}: the log holds {} sets of pressures but the plan lists {} "
        "tests; give the plan one test per hold, in order",
        path, holds.size(), plan.tests.size()));
  }
  for (size_t i = 0; i < holds.size(); ++i) {
    const PressureHold& hold = holds[i];
    // A log in another unit than the plan's is converted: compare to the
    // rounding of its digits, not exactly.
    const double tolerance =
        1e-4 * std::max(1.0, plan.tests[i].pressures.cwiseAbs().maxCoeff());
    if ((hold.pressures - plan.tests[i].pressures).cwiseAbs().maxCoeff() >
        tolerance) {
      throw InputError(fmt::format(
          "{}: hold {} (from t = {} s) is ({}) but plan test '{}' is ({}); "
          "the plan's tests must follow the log's order",
          path, i + 1, hold.start_s, fmt::join(hold.pressures, ", "),
          plan.tests[i].id, fmt::join(plan.tests[i].pressures, ", ")));
    }
  }
  return holds;
}

PressureLogAlignment AlignPressureLog(const std::vector<PressureHold>& holds,
                                      const TestPointDetection& detection,
                                      const std::string& log_path) {
  std::vector<double> offsets, duration_ratios;
  const size_t n = std::min(holds.size(), detection.points.size());
  for (size_t i = 0; i < n; ++i) {
    offsets.push_back(detection.points[i].actuate_s - holds[i].start_s);
    offsets.push_back(detection.points[i].release_s - holds[i].end_s);
    const double seen_s =
        detection.points[i].release_s - detection.points[i].actuate_s;
    if (seen_s > 0.0) {
      duration_ratios.push_back((holds[i].end_s - holds[i].start_s) / seen_s);
    }
  }
  // The log's clock must tick in seconds: holds that last a thousand times
  // the motion's are a clock in milliseconds, and an offset fitted to them
  // would put every window at a time the video does not have.
  if (!duration_ratios.empty()) {
    const double ratio = Median(duration_ratios);
    if (!(ratio > 1.0 / kMaxHoldDurationRatio &&
          ratio < kMaxHoldDurationRatio)) {
      throw InputError(fmt::format(
          "{}: the log's holds last {:.4g} times as long as the heads' "
          "motion shows (median over {} test points){}; time_s must be in "
          "seconds",
          log_path, ratio, duration_ratios.size(),
          std::abs(ratio / 1000.0 - 1.0) < 0.2
              ? ": its clock is in milliseconds, so divide it by 1000"
          : std::abs(ratio * 1000.0 - 1.0) < 0.2
              ? ": its clock is in thousands of seconds"
              : ""));
    }
  }
  PressureLogAlignment alignment;
  if (offsets.empty()) return alignment;
  alignment.offset_s = Median(offsets);
  for (double offset : offsets) {
    alignment.spread_s =
        std::max(alignment.spread_s, std::abs(offset - alignment.offset_s));
  }
  return alignment;
}

}  // namespace softbench
