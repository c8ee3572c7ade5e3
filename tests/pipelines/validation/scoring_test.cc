// ScoreTests on measurements made up frame by frame: what a test point's
// status says when a number it needs is missing or cannot be trusted
// (issue 30: never `ok` without its numbers).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "model/equilibrium.h"
#include "pipelines/validation/validation.h"

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

// Frames at 30 fps up to `end_s`: the head at the model's prediction during
// the hold, at rest before it, and `after_release_mm` along y after it (a
// head still on its way back, or one that slipped).
VideoMeasurement Measurement(const TestPlan& plan, double end_s,
                             double after_release_mm) {
  const EquilibriumProblem problem(plan.mechanism, plan.force_model);
  EquilibriumSolver solver(problem);
  Eigen::VectorXd held = Eigen::VectorXd::Zero(problem.NumUnknowns());
  solver.Solve(plan.tests[0].pressures * plan.mpa_per_unit, &held);
  VideoMeasurement m;
  m.fps = 30.0;
  m.frame_interval_s = 1.0 / 30.0;
  for (int i = 0; i / 30.0 <= end_s; ++i) {
    FrameSample& frame = m.frames.emplace_back();
    frame.frame = i;
    frame.time_s = i / 30.0;
    HeadSample& head = frame.heads.emplace_back();
    head.observation.complete = true;
    head.observation.dots_found = 3;
    head.displacement_mm = frame.time_s < 2.0 ? Eigen::Vector2d::Zero()
                           : frame.time_s < 5.0
                               ? Eigen::Vector2d(held.head<2>())
                               : Eigen::Vector2d(after_release_mm, 0.0);
    head.binary_displacement_mm = head.displacement_mm;
    m.last_frame_s = frame.time_s;
  }
  return m;
}

TEST(ScoreTests, FlagsHysteresisOnASettledFinalWindow) {
  const TestPlan plan = OneTestPlan("6, 6, 0");
  const ValidationResult result =
      ScoreTests(plan, Measurement(plan, 9.0, 0.3), ValidationOptions());
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
      ScoreTests(plan, Measurement(plan, 6.2, 0.3), ValidationOptions());
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
  EXPECT_EQ(
      ScoreTests(in_range, Measurement(in_range, 9.0, 0.0), ValidationOptions())
          .tests[0]
          .beyond_reach,
      "");
  const TestPlan beyond = OneTestPlan("60, 0, 0");
  const ValidationResult result =
      ScoreTests(beyond, Measurement(beyond, 9.0, 0.0), ValidationOptions());
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
  const VideoMeasurement m = Measurement(plan, 9.0, 0.0);
  plan.tests[0].pressures = Eigen::Vector3d(1e300, 0, 0);  // past any parser
  const ValidationResult result = ScoreTests(plan, m, ValidationOptions());
  const TestScore& t = result.tests[0];
  EXPECT_EQ(t.status, "no prediction");
  EXPECT_FALSE(t.scored());
  EXPECT_NE(t.reason.find("finds no equilibrium"), std::string::npos)
      << t.reason;
  EXPECT_EQ(result.model_errors[0].tests, 0);
}

}  // namespace
}  // namespace softbench
