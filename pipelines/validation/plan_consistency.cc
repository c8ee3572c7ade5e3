#include "pipelines/validation/plan_consistency.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

namespace softbench {
namespace {

// The largest distance over the heads between `test`'s measured
// displacements and `entry`'s predicted ones [mm].
double Distance(const TestScore& test, const TestScore& entry) {
  double largest = 0.0;
  for (size_t h = 0; h < test.heads.size(); ++h) {
    largest = std::max(
        largest, (test.heads[h].measured_mm - entry.heads[h].model_mm).norm());
  }
  return largest;
}

double PredictedMotion(const TestScore& entry) {
  double largest = 0.0;
  for (const HeadScore& head : entry.heads) {
    largest = std::max(largest, head.model_mm.norm());
  }
  return largest;
}

// The other entry (with other pressures) whose prediction `tests[i]`'s
// motion fits best, or -1.
int BestOtherEntry(const std::vector<TestScore>& tests, size_t i) {
  int best = -1;
  double best_distance = INFINITY;
  for (size_t j = 0; j < tests.size(); ++j) {
    if (j == i || tests[j].pressures.isApprox(tests[i].pressures, 1e-12)) {
      continue;
    }
    const double distance = Distance(tests[i], tests[j]);
    if (distance < best_distance) {
      best_distance = distance;
      best = static_cast<int>(j);
    }
  }
  return best;
}

}  // namespace

std::vector<std::string> CheckPlanConsistency(const ValidationOptions& options,
                                              std::vector<TestScore>* tests) {
  std::vector<std::string> warnings;
  std::vector<std::string> ids;
  for (size_t i = 0; i < tests->size(); ++i) {
    TestScore& test = (*tests)[i];
    if (!test.measured || !test.predicted) continue;
    const double own = Distance(test, test);
    const bool gross =
        own > std::max(options.mismatch_min_mm,
                       options.mismatch_fraction * PredictedMotion(test));
    const int other = BestOtherEntry(*tests, i);
    const double other_distance =
        other >= 0 ? Distance(test, (*tests)[other]) : INFINITY;
    const bool better_elsewhere =
        other_distance < options.better_match_ratio * own &&
        own - other_distance > options.better_match_margin_mm;
    if (!gross && !better_elsewhere) continue;
    test.matches_plan = false;
    test.status = "mismatch";
    test.reason = fmt::format(
        "its motion is {:.3f} mm from its plan entry's prediction", own);
    if (better_elsewhere) {
      test.reason += fmt::format(
          " but within {:.3f} mm of the prediction for test {} (pressures "
          "{}): the bench order differs from the plan's",
          other_distance, (*tests)[other].id,
          fmt::join((*tests)[other].pressures, ", "));
    }
    test.reason += "; not scored";
    warnings.push_back(fmt::format("test {}: {}", test.id, test.reason));
    ids.push_back(test.id);
  }
  if (ids.empty()) return warnings;
  // When most measured tests do not fit, the assignment itself is wrong
  // (times shifted against the video, a test skipped early on): the few that
  // seem to fit do so by chance (a window on another test's hold, a motion
  // read backwards), so none is scored.
  const auto measured =
      std::count_if(tests->begin(), tests->end(),
                    [](const TestScore& t) { return t.measured; });
  if (2 * std::ssize(ids) > measured) {
    warnings.push_back(fmt::format(
        "the plan does not fit the video: {} of {} measured tests do not "
        "move as their entries predict ({}), so no test is scored; check the "
        "plan's times (or give none, to find the test points from the "
        "motion) and its test order",
        ids.size(), measured, fmt::join(ids, ", ")));
    for (TestScore& test : *tests) {
      if (!test.measured || !test.matches_plan) continue;
      test.matches_plan = false;
      test.status = "mismatch";
      test.reason =
          "most tests do not move as their plan entries predict, so this "
          "one's fit is taken as chance; not scored";
    }
    return warnings;
  }
  warnings.push_back(fmt::format(
      "{} of {} tests do not move as their plan entries predict ({}): check "
      "that the plan lists the tests in the order the bench ran them and "
      "that its times fit the video; mark a test the bench skipped with "
      "'skipped: true' and give a test done again an entry of its own",
      ids.size(), tests->size(), fmt::join(ids, ", ")));
  return warnings;
}

}  // namespace softbench
