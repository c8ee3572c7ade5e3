#ifndef SOFTBENCH_PIPELINES_VALIDATION_PLAN_CONSISTENCY_H_
#define SOFTBENCH_PIPELINES_VALIDATION_PLAN_CONSISTENCY_H_

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "pipelines/validation/validation.h"

namespace softbench {

// Checks that each measured test moved as its own plan entry predicts, so a
// test skipped, repeated or swapped on the bench, or times that are off, is
// named instead of being scored against another test's pressures. A test
// fails the check when its measured displacement is
//  - grossly far from its own prediction (beyond both
//    options.mismatch_min_mm and options.mismatch_fraction of the predicted
//    motion: far above any model error the thesis reports), or
//  - far closer to another entry's prediction (with other pressures) than to
//    its own (options.better_match_ratio, options.better_match_margin_mm).
// Each such test gets matches_plan = false, status "mismatch" and a reason
// naming the entry it fits instead, if any; returns one warning per test,
// and a summary line. When more than half of the measured tests do not fit,
// the plan as a whole does not fit the video (times shifted, a test skipped
// early): then no test is scored, since those that seem to fit do so by
// chance.
std::vector<std::string> CheckPlanConsistency(const ValidationOptions& options,
                                              std::vector<TestScore>* tests);

// The heads' displacements the model predicts [mm: y and z of each head in
// turn] for pressures [MPa]; not finite where it has no prediction.
using PredictHeads = std::function<Eigen::VectorXd(const Eigen::VectorXd&)>;

// When more than half of the measured tests do not move as their entries
// predict (after CheckPlanConsistency) or have no prediction (the model
// fails at pressures far beyond the bench's), whether they move as
// predicted with their pressures read in another unit of kPressureUnits
// than the plan's `unit`: a plan written in kPa for a bench set in psi
// predicts motions several times too small, and every test then fails for
// a reason that the plan's times and order cannot explain. Only tests whose
// heads moved further than options.mismatch_min_mm take part (heads that stayed
// still fit any unit that predicts little motion). Returns a warning naming the
// unit under which at least two and more than half of them fit (by
// CheckPlanConsistency's gross test, against `predict`), or nullopt when
// none does.
std::optional<std::string> PressureUnitThatFits(
    const ValidationOptions& options, const std::vector<TestScore>& tests,
    std::string_view unit, const PredictHeads& predict);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_VALIDATION_PLAN_CONSISTENCY_H_
