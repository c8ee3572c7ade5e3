#ifndef SOFTBENCH_PIPELINES_MEASUREMENT_PRESSURE_LOG_H_
#define SOFTBENCH_PIPELINES_MEASUREMENT_PRESSURE_LOG_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "pipelines/formats/test_plan.h"
#include "pipelines/measurement/test_point_detection.h"
#include "util/csv.h"

namespace softbench {

// A test point as the regulator's microcontroller logged it: the pressures
// held from `start_s` until `end_s`, on the log's own clock.
struct PressureHold {
  double start_s = 0.0;
  double end_s = 0.0;
  Eigen::VectorXd pressures;
};

// The holds of a pressure log (rows time_s, p1..pN; each row's pressures
// hold until the next row's time): maximal runs of equal, not all zero,
// pressures. `tolerance` is in the log's unit.
std::vector<PressureHold> PressureLogHolds(
    const std::vector<double>& times_s,
    const std::vector<Eigen::VectorXd>& pressures, double tolerance);

// The log's clock against the video's: video time = log time + offset_s, the
// median over the test points of (detected - logged) actuation and release
// times; `spread_s` is their largest deviation from it.
struct PressureLogAlignment {
  double offset_s = 0.0;
  double spread_s = 0.0;
};
// The holds of the pressure log at `path` (time_s, p1..pN in the plan's
// unit), one per plan test and in its order; throws InputError naming the
// log, the hold and the test when they disagree. `decimal_mark` is the
// log's, as the user declared it.
std::vector<PressureHold> PlanPressureHolds(const TestPlan& plan,
                                            const std::string& path,
                                            DecimalMark decimal_mark);

// Throws InputError naming `log_path` when the holds last several times as
// long (or as short) as the motion's test points: a clock in other units
// than seconds.
PressureLogAlignment AlignPressureLog(const std::vector<PressureHold>& holds,
                                      const TestPointDetection& detection,
                                      const std::string& log_path);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_MEASUREMENT_PRESSURE_LOG_H_
