// ScoreTests on measurements made up frame by frame: what a test point's
// status says when a number it needs is missing or cannot be trusted
// (issue 30: never `ok` without its numbers).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "pipelines/validation/validation.h"
#include "tests/support/held_measurement.h"

namespace softbench {
namespace {

// One delta test, actuated at 2 s and released at 5 s, with the plan's
// pressures; `end_s` is where the video ends.
TestPlan OneTestPlan(const std::string& pressures) {
  return ParseTestPlan(
      "mechanism: delta\n"
      "pressure_unit: psi\n"
      "calibration: {mm_per_px: 0.1}\n"
      "tests:\n"
      "  - {id: t1, pressures: [" +
          pressures + "], actuate_s: 2, release_s: 5}\n",
      "plan.yaml");
}

TEST(ScoreTests, FlagsHysteresisOnASettledFinalWindow) {
  const TestPlan plan = OneTestPlan("6, 6, 0");
  const ValidationResult result =
      ScoreTests(plan, HeldMeasurement(plan, 9.0, 0.3), ValidationOptions());
  EXPECT_EQ(result.tests[0].status, "hysteresis");
  EXPECT_TRUE(result.tests[0].heads[0].hysteresis_judged);
  EXPECT_EQ(result.hysteresis_flagged, std::vector<std::string>{"t1"});
}

// A video that ends 1.2 s after the release: the final window sees a head
// still moving, which is no evidence of hysteresis (issue 30 flagged 0.65
// mm on one).
TEST(ScoreTests, DoesNotJudgeHysteresisWhenTheVideoEndsBeforeTheHeadSettles) {
  const TestPlan plan = OneTestPlan("6, 6, 0");
  const ValidationResult result =
      ScoreTests(plan, HeldMeasurement(plan, 6.2, 0.3), ValidationOptions());
  const TestScore& t = result.tests[0];
  EXPECT_EQ(t.status, "ok");
  EXPECT_FALSE(t.heads[0].hysteresis_judged);
  EXPECT_TRUE(result.hysteresis_flagged.empty());
  EXPECT_NE(t.reason.find("hysteresis not judged"), std::string::npos)
      << t.reason;
  EXPECT_TRUE(t.scored());  // the displacement itself is fine
}

// Within the characterised range every prediction is within reach; well
// beyond it the model's head is somewhere no bench pressure puts it.
TEST(ScoreTests, MarksAPredictionBeyondTheMechanismsReach) {
  const TestPlan in_range = OneTestPlan("6, 6, 0");
  EXPECT_EQ(ScoreTests(in_range, HeldMeasurement(in_range, 9.0, 0.0),
                       ValidationOptions())
                .tests[0]
                .beyond_reach,
            "");
  const TestPlan beyond = OneTestPlan("60, 0, 0");
  const ValidationResult result = ScoreTests(
      beyond, HeldMeasurement(beyond, 9.0, 0.0), ValidationOptions());
  EXPECT_NE(result.tests[0].beyond_reach.find("beyond where pressures up to "
                                              "the characterised 6 psi reach"),
            std::string::npos)
      << result.tests[0].beyond_reach;
  bool warned = false;
  for (const std::string& w : result.warnings) {
    warned |= w.find("t1: the model puts the heads") != std::string::npos;
  }
  EXPECT_TRUE(warned);
}

// No equilibrium at the test's pressures: nothing to score against, so the
// test is "no prediction", not "ok" with empty model columns.
TEST(ScoreTests, NeverCallsATestOkWithoutAPrediction) {
  TestPlan plan = OneTestPlan("6, 6, 0");
  const VideoMeasurement m = HeldMeasurement(plan, 9.0, 0.0);
  plan.tests[0].pressures = Eigen::Vector3d(1e300, 0, 0);  // past any parser
  const ValidationResult result = ScoreTests(plan, m, ValidationOptions());
  const TestScore& t = result.tests[0];
  EXPECT_EQ(t.status, "no prediction");
  EXPECT_FALSE(t.scored());
  EXPECT_NE(t.reason.find("finds no equilibrium"), std::string::npos)
      << t.reason;
  EXPECT_EQ(result.model_errors[0].tests, 0);
}

// The dots' term of a budget, or -1 without one.
double DotsTermMm(const UncertaintyBudget& budget) {
  for (const UncertaintyTerm& term : budget.terms) {
    if (term.name == "dots") return term.u_mm.x();
  }
  return -1.0;
}

// A phone's sharpening moves each dot by where its edge falls on the pixel
// grid: an error that changes when the head moves and repeats when it is
// back at rest. The actuated changes' dots disagree, the final ones' do
// not, and each budget takes its own kind's disagreement.
TEST(ScoreTests, PoolsTheDotsOfActuatedAndFinalChangesApart) {
  TestPlan plan = ParseTestPlan(
      "mechanism: delta\n"
      "pressure_unit: psi\n"
      "calibration: {mm_per_px: 0.1}\n"
      "tests:\n"
      "  - {id: t1, pressures: [6, 6, 0], actuate_s: 2, release_s: 5}\n"
      "  - {id: t2, pressures: [0, 6, 6], actuate_s: 10, release_s: 13}\n"
      "  - {id: t3, pressures: [6, 0, 6], actuate_s: 18, release_s: 21}\n",
      "plan.yaml");
  VideoMeasurement m = HeldMeasurement(plan, 26.0, 0.0);
  const std::vector<Eigen::Vector2d> layout = {
      {-5.5, -3.2}, {5.5, -3.2}, {0.0, 6.4}};
  for (FrameSample& f : m.frames) {
    for (HeadSample& head : f.heads) {
      const Eigen::Vector2d at = head.observation.position_mm;
      for (size_t d = 0; d < layout.size(); ++d) {
        // A bias of 0.002 mm that follows the head's place, as a pixel
        // phase does, and is the same at every return to rest.
        const double phase = 1e3 * at.x() + 7e2 * at.y() + 2.1 * d;
        DotObservation& dot = head.observation.dots.emplace_back();
        dot.found = true;
        dot.plane_mm =
            at + layout[d] +
            0.002 * Eigen::Vector2d(std::sin(phase), std::cos(1.3 * phase));
      }
    }
  }
  const ValidationResult result = ScoreTests(plan, m, ValidationOptions());
  for (const TestScore& t : result.tests) {
    ASSERT_TRUE(t.measured) << t.id;
    EXPECT_GT(DotsTermMm(t.heads[0].budget), 4e-4) << t.id;
    EXPECT_NEAR(DotsTermMm(t.heads[0].hysteresis_budget), 0.0, 1e-9) << t.id;
  }
}

}  // namespace
}  // namespace softbench
