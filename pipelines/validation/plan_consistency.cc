#include "pipelines/validation/plan_consistency.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>

#include "model/units.h"

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

// Whether a test `own` [mm] from its entry's prediction, which moves the
// heads by up to `predicted` [mm], is far beyond any model error.
bool Gross(const ValidationOptions& options, double own, double predicted) {
  return own > std::max(options.mismatch_min_mm,
                        options.mismatch_fraction * predicted);
}

// The other entry (with other pressures and a prediction) whose prediction
// `tests[i]`'s motion fits best, or -1.
int BestOtherEntry(const std::vector<TestScore>& tests, size_t i) {
  int best = -1;
  double best_distance = INFINITY;
  for (size_t j = 0; j < tests.size(); ++j) {
    // An entry the model has no prediction for is nobody's match (its NaN
    // distance would read as 0 through std::max).
    if (j == i || !tests[j].predicted ||
        tests[j].pressures.isApprox(tests[i].pressures, 1e-12)) {
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
    const bool gross = Gross(options, own, PredictedMotion(test));
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

std::optional<std::string> PressureUnitThatFits(
    const ValidationOptions& options, const std::vector<TestScore>& tests,
    std::string_view unit, const PredictHeads& predict) {
  const auto measured =
      std::count_if(tests.begin(), tests.end(),
                    [](const TestScore& t) { return t.measured; });
  const auto failed =
      std::count_if(tests.begin(), tests.end(), [](const TestScore& t) {
        return t.measured && !(t.matches_plan && t.predicted);
      });
  if (2 * failed <= measured) return std::nullopt;
  // Only a test that moved further than the gate's floor can tell units
  // apart: heads that stayed still (windows that missed the actuation) fit
  // any unit that predicts little motion.
  const auto moved = [&](const TestScore& t) {
    return t.measured &&
           std::any_of(t.heads.begin(), t.heads.end(), [&](const HeadScore& h) {
             return h.measured_mm.norm() > options.mismatch_min_mm;
           });
  };
  const auto movers = std::count_if(tests.begin(), tests.end(), moved);
  const PressureUnit* plan_unit = FindPressureUnit(unit);
  const PressureUnit* best = nullptr;
  int best_fits = 0;
  for (const PressureUnit& other : kPressureUnits) {
    if (&other == plan_unit) continue;
    int fits = 0;
    for (const TestScore& test : tests) {
      const Eigen::VectorXd mpa = test.pressures * other.mpa_per_unit;
      if (!moved(test) || mpa.maxCoeff() > kMaxPlausiblePressureMpa) continue;
      const Eigen::VectorXd model = predict(mpa);
      if (!model.allFinite()) continue;
      // The test's entry as this unit would predict it, judged as
      // CheckPlanConsistency judges the plan's own.
      TestScore entry = test;
      for (size_t h = 0; h < entry.heads.size(); ++h) {
        entry.heads[h].model_mm = model.segment<2>(2 * h);
      }
      if (!Gross(options, Distance(test, entry), PredictedMotion(entry))) {
        ++fits;
      }
    }
    if (fits >= 2 && 2 * fits > movers && fits > best_fits) {
      best = &other;
      best_fits = fits;
    }
  }
  if (best == nullptr) return std::nullopt;
  return fmt::format(
      "with their pressures read in {} instead of the plan's {}, {} of the "
      "{} measured tests that moved over {:g} mm move as the model predicts: "
      "if the bench's pressures were in {}, set pressure_unit: {} in the plan",
      best->name, unit, best_fits, movers, options.mismatch_min_mm, best->name,
      best->name);
}

}  // namespace softbench
