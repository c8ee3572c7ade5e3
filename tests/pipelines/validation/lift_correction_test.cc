// The lift correction's decision (pipelines/validation/lift_correction.h):
// a chi-squared test of the heads' actuated lifts against their u, on
// scores and measurements made up with known lifts (no video).
#include "pipelines/validation/lift_correction.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "tests/support/held_measurement.h"

namespace softbench {
namespace {

// A score of `tests` tests of `heads` heads, each actuated lift drawn from
// N(lift_mm, u_mm) with its u, and the codec's term on `codec_jumps`.
ValidationResult ScoreWithLifts(int tests, int heads, double lift_mm,
                                double u_mm, int codec_jumps,
                                std::mt19937* random) {
  // Scaled by hand: u_mm may be 0, which a distribution may not have.
  std::normal_distribution<double> noise;
  ValidationResult result;
  result.codec_jumps = codec_jumps;
  for (int t = 0; t < tests; ++t) {
    TestScore& score = result.tests.emplace_back();
    score.measured = true;
    for (int h = 0; h < heads; ++h) {
      HeadScore& head = score.heads.emplace_back();
      head.lift_mm = lift_mm + u_mm * noise(*random);
      head.u_lift_mm = u_mm;
    }
  }
  return result;
}

// Heads that stay in the plane are corrected as often as the test's
// significance says, no more: its false alarms over many made-up videos.
TEST(DecideLiftCorrection, CorrectsFlatHeadsAsRarelyAsItsSignificance) {
  std::mt19937 random(27);
  const LiftCorrectionOptions options;  // auto, significance 0.01
  constexpr int kVideos = 4000;
  int corrected = 0;
  for (int i = 0; i < kVideos; ++i) {
    const LiftCorrectionDecision d = DecideLiftCorrection(
        ScoreWithLifts(10, 2, 0.0, 0.1, 20, &random), 10, options);
    EXPECT_EQ(d.lifts, 20);
    EXPECT_GE(d.p_value, 0.0);
    EXPECT_LE(d.p_value, 1.0);
    corrected += d.correct;
  }
  // 1 % of 4000 is 40, with a binomial standard deviation of 6.3.
  EXPECT_GT(corrected, 40 - 4 * 6.3);
  EXPECT_LT(corrected, 40 + 4 * 6.3);
}

// Lifts of three times their u, as the lift bench's heads show (0.3-0.6 mm
// against u of 0.05-0.15 mm), are taken out.
TEST(DecideLiftCorrection, CorrectsHeadsThatLeaveThePlane) {
  std::mt19937 random(28);
  const LiftCorrectionDecision d = DecideLiftCorrection(
      ScoreWithLifts(10, 1, 0.3, 0.1, 20, &random), 10, {});
  EXPECT_TRUE(d.correct);
  EXPECT_LT(d.p_value, 1e-6);
  EXPECT_NE(d.reason.find("taken out: the heads leave the plane"),
            std::string::npos)
      << d.reason;
}

// The p-value is the chi-squared distribution's upper tail: one lift of
// 1.96 u has p 0.05, two lifts of u each (chi-squared 2) have p exp(-1).
TEST(DecideLiftCorrection, PValueIsTheChiSquaredUpperTail) {
  ValidationResult one;
  one.codec_jumps = 10;
  one.tests.emplace_back().measured = true;
  one.tests[0].heads.push_back(HeadScore{});
  one.tests[0].heads[0].lift_mm = 1.959963985 * 0.1;
  one.tests[0].heads[0].u_lift_mm = 0.1;
  EXPECT_NEAR(DecideLiftCorrection(one, 10, {}).p_value, 0.05, 1e-9);
  ValidationResult two = one;
  two.tests[0].heads[0].lift_mm = -0.1;
  two.tests[0].heads.push_back(two.tests[0].heads[0]);
  two.tests[0].heads[1].lift_mm = 0.1;
  const LiftCorrectionDecision d = DecideLiftCorrection(two, 10, {});
  EXPECT_EQ(d.lifts, 2);
  EXPECT_NEAR(d.chi_squared, 2.0, 1e-12);
  EXPECT_NEAR(d.p_value, std::exp(-1.0), 1e-12);
}

// Without the codec's term a flat head's lift looks significant (its u
// too small by the codec's error in the dots' spacing): auto leaves the
// parallax in, and says why.
TEST(DecideLiftCorrection, LeavesItInWithoutTheCodecsTerm) {
  std::mt19937 random(29);
  const LiftCorrectionDecision d =
      DecideLiftCorrection(ScoreWithLifts(10, 1, 0.3, 0.1, 3, &random), 10, {});
  EXPECT_FALSE(d.correct);
  EXPECT_LT(d.p_value, 1e-6);
  EXPECT_NE(d.reason.find("lacks the codec's term (3 jumps"), std::string::npos)
      << d.reason;
}

// Unmeasured tests and lifts without a u are not counted; with none left
// there is nothing to take out.
TEST(DecideLiftCorrection, CountsOnlyMeasuredLiftsWithAU) {
  std::mt19937 random(30);
  ValidationResult result = ScoreWithLifts(3, 1, 0.3, 0.1, 20, &random);
  result.tests[0].measured = false;
  result.tests[1].heads[0].u_lift_mm = NAN;
  EXPECT_EQ(DecideLiftCorrection(result, 10, {}).lifts, 1);
  result.tests[2].heads[0].lift_mm = NAN;
  const LiftCorrectionDecision none = DecideLiftCorrection(result, 10, {});
  EXPECT_EQ(none.lifts, 0);
  EXPECT_FALSE(none.correct);
  EXPECT_TRUE(std::isnan(none.p_value));
}

// --lift-correction and --no-lift-correction decide as told, whatever the
// lifts show, and keep the test's figures for the record.
TEST(DecideLiftCorrection, ForcedModesDecideAsTold) {
  std::mt19937 random(31);
  const ValidationResult flat = ScoreWithLifts(10, 1, 0.0, 0.1, 20, &random);
  const ValidationResult lifting = ScoreWithLifts(10, 1, 0.3, 0.1, 20, &random);
  const LiftCorrectionDecision always =
      DecideLiftCorrection(flat, 10, {.mode = LiftCorrectionMode::kEveryHead});
  EXPECT_TRUE(always.correct);
  EXPECT_EQ(always.lifts, 10);
  const LiftCorrectionDecision never =
      DecideLiftCorrection(lifting, 10, {.mode = LiftCorrectionMode::kNone});
  EXPECT_FALSE(never.correct);
  EXPECT_LT(never.p_value, 1e-6);
}

TEST(LiftCorrectionOptions, SignificanceMustBeAProbability) {
  EXPECT_FALSE(LiftCorrectionOptions{}.Problem());
  for (double bad : {0.0, 1.0, -0.1, std::nan("")}) {
    EXPECT_TRUE(LiftCorrectionOptions{.significance = bad}.Problem()) << bad;
  }
}

// A made-up delta measurement whose head rises `lift_mm` while held (each
// frame's lift with noise of 0.05 mm), its dots' apparent centre moved by
// its parallax of 0.01 mm along y per millimetre of lift.
VideoMeasurement LiftingMeasurement(const TestPlan& plan, double lift_mm) {
  VideoMeasurement m = HeldMeasurement(plan, 20.0, 0.0);
  LiftHeldHead(plan, lift_mm, 0.05, 0.01, &m);
  for (FrameSample& f : m.frames) {
    f.heads[0].displacement_mm += f.heads[0].parallax_mm;
  }
  return m;
}

// A head that rises 0.5 mm: auto takes its parallax out of every frame and
// scores again, so the displacement is the head's motion in the plane and
// its budget has no parallax term.
TEST(ScoreTestsCorrectingLift, TakesOutTheParallaxOfHeadsThatLift) {
  const TestPlan plan = HeldDeltaPlan();
  VideoMeasurement m = LiftingMeasurement(plan, 0.5);
  const VideoMeasurement before = m;
  const ValidationResult left_in = ScoreTests(plan, m, ValidationOptions());
  const LiftCorrectedScore score =
      ScoreTestsCorrectingLift(plan, ValidationOptions(), {}, &m);
  ASSERT_TRUE(score.decision.correct) << score.decision.reason;
  EXPECT_TRUE(m.lift_corrected);
  for (size_t i = 0; i < m.frames.size(); ++i) {
    const HeadSample& s = m.frames[i].heads[0];
    EXPECT_EQ(s.displacement_mm,
              before.frames[i].heads[0].displacement_mm - s.parallax_mm);
  }
  for (size_t t = 0; t < score.result.tests.size(); ++t) {
    const HeadScore& corrected = score.result.tests[t].heads[0];
    const HeadScore& uncorrected = left_in.tests[t].heads[0];
    // The actuated window's parallax, about 0.005 mm along y, is gone.
    EXPECT_NEAR(uncorrected.measured_mm.x() - corrected.measured_mm.x(), 0.005,
                0.001)
        << score.result.tests[t].id;
    for (const UncertaintyTerm& term : corrected.budget.terms) {
      EXPECT_NE(term.name, "parallax") << score.result.tests[t].id;
    }
  }
}

// A head that stays in the plane is scored once, its positions as measured.
TEST(ScoreTestsCorrectingLift, LeavesFlatHeadsAsMeasured) {
  const TestPlan plan = HeldDeltaPlan();
  VideoMeasurement m = LiftingMeasurement(plan, 0.0);
  const VideoMeasurement before = m;
  const LiftCorrectedScore score =
      ScoreTestsCorrectingLift(plan, ValidationOptions(), {}, &m);
  EXPECT_FALSE(score.decision.correct) << score.decision.reason;
  EXPECT_EQ(score.decision.lifts, 3);
  EXPECT_FALSE(m.lift_corrected);
  for (size_t i = 0; i < m.frames.size(); ++i) {
    EXPECT_EQ(m.frames[i].heads[0].displacement_mm,
              before.frames[i].heads[0].displacement_mm);
  }
}

// --lift-correction where no frame has a lift (no pose fitted): nothing is
// taken out, and the decision says so rather than that it corrected.
TEST(ScoreTestsCorrectingLift, SaysWhenThereIsNothingToTakeOut) {
  const TestPlan plan = HeldDeltaPlan();
  VideoMeasurement m = HeldMeasurement(plan, 20.0, 0.0);  // no poses
  const VideoMeasurement before = m;
  const LiftCorrectedScore score = ScoreTestsCorrectingLift(
      plan, ValidationOptions(), {.mode = LiftCorrectionMode::kEveryHead}, &m);
  EXPECT_FALSE(score.decision.correct);
  EXPECT_FALSE(m.lift_corrected);
  EXPECT_NE(score.decision.reason.find("nothing taken out"), std::string::npos)
      << score.decision.reason;
  for (size_t i = 0; i < m.frames.size(); ++i) {
    EXPECT_EQ(m.frames[i].heads[0].displacement_mm,
              before.frames[i].heads[0].displacement_mm);
  }
}

}  // namespace
}  // namespace softbench
