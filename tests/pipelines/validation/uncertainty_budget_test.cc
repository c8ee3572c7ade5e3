// The uncertainty budget (pipelines/validation/uncertainty_budget.h): its
// pieces' maths, and its coverage on measurements made up with the errors a
// codec makes (a level per head repeated from one I picture to the next,
// each dot's own, and per-frame noise), where the truth is known exactly.
#include "pipelines/validation/uncertainty_budget.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "pipelines/measurement/plan_camera.h"
#include "pipelines/validation/validation.h"
#include "tests/support/coverage.h"
#include "tests/support/held_measurement.h"

namespace softbench {
namespace {

// A window whose head `0` has dots at `dots` (its median positions) and no
// lift.
WindowSummary WindowWithDots(const std::vector<Eigen::Vector2d>& dots) {
  WindowSummary w;
  w.dot_median_mm = {dots};
  w.standard_error_mm = {Eigen::Vector2d::Zero()};
  w.parallax_mm = {Eigen::Vector2d::Constant(NAN)};  // no lift measured
  return w;
}

// A head's own motion is not the dots' error: a shift, a turn and the
// change of scale of a lift toward the camera leave no residual.
TEST(DotsSimilarityResidual, IsZeroForAShiftATurnAndALiftsScale) {
  const std::vector<Eigen::Vector2d> before = {
      {-5.0, -2.9}, {5.0, -2.9}, {0.0, 5.8}};
  const double turn = 2e-4;                  // rad, as a head turns under load
  const double scale = 0.6 / (475.0 - 0.6);  // a 0.6 mm lift at 475 mm
  const Eigen::Rotation2Dd rotation(turn);
  std::vector<Eigen::Vector2d> after;
  for (const Eigen::Vector2d& p : before) {
    after.emplace_back((1.0 + scale) * (rotation * p) +
                       Eigen::Vector2d(0.7, -0.4));
  }
  const SimilarityResidual r =
      DotsSimilarityResidual(WindowWithDots(before), WindowWithDots(after), 0);
  EXPECT_EQ(r.dof, 2);
  // The small-angle fit leaves about turn^2 x radius: 2e-7 mm.
  EXPECT_LT(std::sqrt(r.sum_of_squares_mm2), 1e-6);
  // A dot moved on its own is seen.
  after[2].y() += 0.004;
  EXPECT_GT(std::sqrt(DotsSimilarityResidual(WindowWithDots(before),
                                             WindowWithDots(after), 0)
                          .sum_of_squares_mm2),
            0.002);
}

// Pooled over many changes, the residual estimates one dot's scatter: each
// dot's change has the scatter of two windows, sqrt(2) sigma per axis,
// whatever the head's lift scales its dots by.
TEST(DotsSimilarityResidual, PooledEstimatesTheDotsScatter) {
  std::mt19937 random(11);
  std::normal_distribution<double> normal(0.0, 0.003);
  std::uniform_real_distribution<double> lift_scale(0.0, 0.0013);
  const std::vector<Eigen::Vector2d> layout = {
      {-5.0, -2.9}, {5.0, -2.9}, {0.0, 5.8}};
  double squares = 0.0;
  int dof = 0;
  for (int i = 0; i < 400; ++i) {
    std::vector<Eigen::Vector2d> a, b;
    const double scale = 1.0 + lift_scale(random);
    for (const Eigen::Vector2d& p : layout) {
      a.emplace_back(p + Eigen::Vector2d(normal(random), normal(random)));
      b.emplace_back(scale * p +
                     Eigen::Vector2d(1.0 + normal(random), normal(random)));
    }
    const SimilarityResidual r =
        DotsSimilarityResidual(WindowWithDots(a), WindowWithDots(b), 0);
    squares += r.sum_of_squares_mm2;
    dof += r.dof;
  }
  EXPECT_NEAR(std::sqrt(squares / dof), std::sqrt(2.0) * 0.003, 0.0002);
}

TEST(DotsSimilarityResidual, NeedsThreeDots) {
  const std::vector<Eigen::Vector2d> two = {{0.0, 0.0}, {10.0, 0.0}};
  EXPECT_EQ(
      DotsSimilarityResidual(WindowWithDots(two), WindowWithDots(two), 0).dof,
      0);
}

TEST(UncertaintyBudget, AddsIndependentTermsInQuadrature) {
  const std::vector<Eigen::Vector2d> dots = {{0, 0}, {1, 0}, {0, 1}};
  WindowSummary from = WindowWithDots(dots), to = WindowWithDots(dots);
  from.standard_error_mm = {Eigen::Vector2d(0.003, 0.0)};
  to.standard_error_mm = {Eigen::Vector2d(0.004, 0.0)};
  HeadUncertaintyContext context;
  context.dot_sigma_mm = 0.012 * std::sqrt(3.0);  // 0.012 per axis
  context.dot_dof = 30;
  context.codec_level_mm2 = Eigen::Vector2d(0.0, 0.5 * 0.02 * 0.02);
  context.codec_jumps = 10;
  const UncertaintyBudget b = ChangeBudget(from, to, 0, context);
  ASSERT_EQ(b.terms.size(), 3u);
  EXPECT_NEAR(b.u_mm.x(), std::hypot(0.005, 0.012), 1e-12);
  EXPECT_NEAR(b.u_mm.y(), std::hypot(0.012, 0.02), 1e-12);
  EXPECT_NEAR(b.TotalMm(), b.u_mm.norm(), 1e-15);
  EXPECT_EQ(b.Largest(), "codec");
}

// The held measurement of `plan` with a codec's errors: every `gop` frames
// an I picture draws the head afresh with a new level error (sigma
// `level_mm` per axis) and each dot a new error of its own (`dot_mm`); the
// frames between repeat them, plus per-frame noise `noise_mm`.
VideoMeasurement CodecLikeMeasurement(const TestPlan& plan, double end_s,
                                      int gop, double level_mm, double dot_mm,
                                      double noise_mm, uint32_t seed) {
  VideoMeasurement m = HeldMeasurement(plan, end_s, 0.0);
  std::mt19937 random(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  const auto draw = [&](double sigma) {
    return Eigen::Vector2d(sigma * normal(random), sigma * normal(random));
  };
  const std::vector<Eigen::Vector2d>& layout = plan.markers[0].layout_mm;
  Eigen::Vector2d level = Eigen::Vector2d::Zero();
  std::vector<Eigen::Vector2d> dot_errors(layout.size());
  for (FrameSample& f : m.frames) {
    f.intra = f.frame % gop == 0;
    if (f.intra) {
      level = draw(level_mm);
      for (Eigen::Vector2d& e : dot_errors) e = draw(dot_mm);
    }
    HeadSample& head = f.heads[0];
    const Eigen::Vector2d truth = head.displacement_mm;
    head.observation.dots.clear();
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (size_t d = 0; d < layout.size(); ++d) {
      DotObservation& dot = head.observation.dots.emplace_back();
      dot.found = true;
      dot.plane_mm = truth + layout[d] + level + dot_errors[d] + draw(noise_mm);
      centre += (dot.plane_mm - layout[d]) / layout.size();
    }
    head.displacement_mm = centre;
    head.observation.position_mm = centre;
  }
  return m;
}

// The budget's promise on errors of the kind it models: at least 95 % of
// displacements within U = 2u, 60 % within u, and u not inflated (median u
// at most 2x the RMS error), over 4 videos of 40 test points.
TEST(UncertaintyBudget, CoversCodecLikeErrorsAtTheStatedRates) {
  const TestPlan plan = TimedDeltaPlan(40);
  const VideoMeasurement held = HeldMeasurement(plan, 245.0, 0.0);
  const ValidationResult truth = ScoreTests(plan, held, ValidationOptions());
  std::vector<double> errors, u;
  for (uint32_t seed = 1; seed <= 4; ++seed) {
    const VideoMeasurement m =
        CodecLikeMeasurement(plan, 245.0, 37, 0.004, 0.003, 0.0005, seed);
    const ValidationResult r = ScoreTests(plan, m, ValidationOptions());
    for (size_t i = 0; i < r.tests.size(); ++i) {
      ASSERT_TRUE(r.tests[i].measured) << r.tests[i].reason;
      const HeadScore& s = r.tests[i].heads[0];
      errors.push_back(
          (s.measured_mm - truth.tests[i].heads[0].measured_mm).norm());
      u.push_back(s.budget.TotalMm());
      // Window scatter, dots, codec and scale, each measured.
      ASSERT_EQ(s.budget.terms.size(), 4u);
      EXPECT_EQ(s.budget.terms[2].name, "codec");
      EXPECT_EQ(s.budget.terms[3].name, "scale");
    }
  }
  ExpectCoverageTargets(errors, u);
}

// Without still I pictures the codec's term cannot be measured, and the
// result says so; with enough of them it does not.
TEST(ScoreTests, WarnsWhenTheCodecTermRestsOnTooFewJumps) {
  const TestPlan plan = TimedDeltaPlan(8);
  const auto warned = [&](const VideoMeasurement& m) {
    for (const std::string& w :
         ScoreTests(plan, m, ValidationOptions()).warnings) {
      if (w.find("codec term rests on") != std::string::npos) return true;
    }
    return false;
  };
  EXPECT_TRUE(warned(HeldMeasurement(plan, 50.0, 0.0)));  // no I picture
  EXPECT_FALSE(
      warned(CodecLikeMeasurement(plan, 50.0, 37, 0.004, 0.003, 0.0005, 1)));
}

// A head still between I pictures jumps at each by the difference of two
// levels, and so does its lift; a moving head gives no jumps.
TEST(StillIntraJumps, MeasuresTheLevelsOfAStillHeadOnly) {
  const TestPlan plan = TimedDeltaPlan(4);
  VideoMeasurement m =
      CodecLikeMeasurement(plan, 25.0, 20, 0.004, 0.0, 0.0002, 7);
  ASSERT_TRUE(std::isnan(StillIntraJumps(m, 0)[0].lift_mm));
  for (FrameSample& f : m.frames) {
    f.heads[0].lift_mm = 3.0 * f.heads[0].displacement_mm.y();
  }
  const std::vector<IntraJump> jumps = StillIntraJumps(m, 0);
  ASSERT_GE(jumps.size(), 20u);
  double squares = 0.0;
  for (const IntraJump& j : jumps) {
    squares += j.position_mm.squaredNorm();
    EXPECT_NEAR(j.lift_mm, 3.0 * j.position_mm.y(), 1e-12);
  }
  // Two axes, two levels each: 4 sigma^2 on average.
  EXPECT_NEAR(std::sqrt(squares / jumps.size() / 4.0), 0.004, 0.0012);
  const CodecLevel level = MeasureCodecLevel(m);
  EXPECT_NEAR(level.lift_variance_mm2, 9.0 * level.variance_mm2.y(), 1e-15);

  VideoMeasurement moving = m;
  for (FrameSample& f : moving.frames) {
    f.heads[0].displacement_mm.x() += 0.01 * f.frame;  // 1 px a frame
  }
  EXPECT_TRUE(StillIntraJumps(moving, 0).empty());
}

// Frames that scatter by more than kStillPx (a phone's noise, a trembling
// tripod's residue) still show a still head's jumps at its I pictures,
// measured at their level; a head moving a pixel a frame shows none.
TEST(StillIntraJumps, FindsAStillHeadInNoisyFrames) {
  const TestPlan plan = TimedDeltaPlan(4);
  const VideoMeasurement quiet =
      CodecLikeMeasurement(plan, 25.0, 20, 0.004, 0.0, 0.0002, 7);
  const double floor_mm = kStillPx * quiet.mm_per_px;
  EXPECT_DOUBLE_EQ(StillRangeMm(quiet, 0), floor_mm);
  // 0.015 mm per dot: 0.0087 mm (0.087 px) for the head's centre a frame.
  const VideoMeasurement noisy =
      CodecLikeMeasurement(plan, 25.0, 20, 0.004, 0.0, 0.015, 7);
  EXPECT_GT(StillRangeMm(noisy, 0), 3.0 * floor_mm);
  const std::vector<IntraJump> jumps = StillIntraJumps(noisy, 0);
  ASSERT_GE(jumps.size(), 20u);
  double squares = 0.0;
  for (const IntraJump& j : jumps) squares += j.position_mm.squaredNorm();
  // The level's 0.004 mm and what the frames' noise leaves in the medians
  // of up to 8 frames either side.
  EXPECT_NEAR(std::sqrt(squares / jumps.size() / 4.0), 0.0055, 0.0015);

  VideoMeasurement moving = noisy;
  for (FrameSample& f : moving.frames) {
    f.heads[0].displacement_mm.x() += moving.mm_per_px * f.frame;  // 1 px
  }
  EXPECT_TRUE(StillIntraJumps(moving, 0).empty());
}

// With the intrinsics' standard errors known, the budget has their term.
TEST(UncertaintyBudget, HasTheIntrinsicsTermWhenTheirErrorsAreKnown) {
  const std::vector<Eigen::Vector2d> dots = {{0, 0}, {1, 0}, {0, 1}};
  WindowSummary from = WindowWithDots(dots), to = WindowWithDots(dots);
  from.median_mm = {Eigen::Vector2d::Zero()};
  to.median_mm = {Eigen::Vector2d(1.5, -0.8)};
  const TestPlan plan = TimedDeltaPlan(1);
  CameraIntrinsics k =
      CameraIntrinsics::FromEquivalentFocalLength(26, 1920, 1080);
  k.distortion = {-0.1, 0.0, 0.0, 0.0, 0.0};
  k.distortion_std = {0.01, 0.0, 0.0, 0.0, 0.0};
  const PlaneMapping mapping = PlaneMapping::FromScale(k, 0.2, 0.0);
  const IntrinsicsSensitivity sensitivity(plan, k, mapping, std::nullopt);
  HeadUncertaintyContext context;
  context.intrinsics = &sensitivity;
  context.rest_mm = Eigen::Vector2d(120.0, 60.0);
  const UncertaintyBudget b = ChangeBudget(from, to, 0, context);
  ASSERT_EQ(b.terms.size(), 2u);
  EXPECT_EQ(b.terms[1].name, "intrinsics");
  const Eigen::Vector2d expected = sensitivity.ChangeUncertaintyMm(
      context.rest_mm, context.rest_mm + to.median_mm[0]);
  EXPECT_GT(expected.norm(), 0.0);
  EXPECT_NEAR((b.terms[1].u_mm - expected).norm(), 0.0, 1e-15);
  context.intrinsics = nullptr;
  EXPECT_EQ(ChangeBudget(from, to, 0, context).terms.size(), 1u);
}

// Positions that still carry the lift's parallax (no --lift-correction):
// the parallax measured between the windows is a term, axis by axis, so a
// lifting head's U covers the error it leaves; corrected positions, or
// windows without a lift, have none.
TEST(UncertaintyBudget, CountsTheParallaxLeftInThePositions) {
  const std::vector<Eigen::Vector2d> dots = {{0, 0}, {1, 0}, {0, 1}};
  WindowSummary from = WindowWithDots(dots), to = WindowWithDots(dots);
  from.median_mm = {Eigen::Vector2d::Zero()};
  to.median_mm = {Eigen::Vector2d(1.5, -0.8)};
  from.parallax_mm = {Eigen::Vector2d(0.001, -0.002)};
  to.parallax_mm = {Eigen::Vector2d(-0.020, 0.003)};
  HeadUncertaintyContext context;
  context.parallax_in_positions = true;
  const UncertaintyBudget b = ChangeBudget(from, to, 0, context);
  ASSERT_EQ(b.terms.size(), 2u);
  EXPECT_EQ(b.terms[1].name, "parallax");
  EXPECT_NEAR((b.terms[1].u_mm - Eigen::Vector2d(0.021, 0.005)).norm(), 0.0,
              1e-15);
  EXPECT_EQ(b.Largest(), "parallax");
  context.parallax_in_positions = false;
  EXPECT_EQ(ChangeBudget(from, to, 0, context).terms.size(), 1u);
  context.parallax_in_positions = true;
  to.parallax_mm = {Eigen::Vector2d::Constant(NAN)};  // no lift measured
  EXPECT_EQ(ChangeBudget(from, to, 0, context).terms.size(), 1u);
}

// Hysteresis is judged against its U: a slip of 0.3 mm exceeds 0.05 mm
// whatever the noise; one of 0.05 mm against 0.05 mm cannot be told.
TEST(ScoreTests, JudgesHysteresisAgainstItsUncertainty) {
  const TestPlan plan = ParseTestPlan(
      "mechanism: delta\n"
      "pressure_unit: psi\n"
      "calibration: {mm_per_px: 0.1}\n"
      "tests:\n"
      "  - {id: t1, pressures: [6, 6, 0], actuate_s: 2, release_s: 5}\n",
      "plan.yaml");
  for (const auto& [slip_mm, verdict, status] :
       {std::tuple{0.3, kHysteresisExceeds, "hysteresis"},
        std::tuple{0.05, kHysteresisCannotTell, "ok"},
        std::tuple{0.0, kHysteresisWithin, "ok"}}) {
    VideoMeasurement m = HeldMeasurement(plan, 9.0, slip_mm);
    std::mt19937 random(5);
    std::normal_distribution<double> noise(0.0, 0.002);
    for (FrameSample& f : m.frames) {
      f.heads[0].displacement_mm += Eigen::Vector2d(noise(random), 0.0);
    }
    const ValidationResult r = ScoreTests(plan, m, ValidationOptions());
    const HeadScore& head = r.tests[0].heads[0];
    EXPECT_GT(head.hysteresis_budget.TotalMm(), 0.0);
    EXPECT_EQ(head.hysteresis_verdict, verdict) << slip_mm;
    EXPECT_EQ(r.tests[0].status, status) << slip_mm;
  }
}

}  // namespace
}  // namespace softbench
