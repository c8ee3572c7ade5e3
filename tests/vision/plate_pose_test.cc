#include "vision/plate_pose.h"

#include <gtest/gtest.h>

#include <array>
#include <numbers>
#include <random>

namespace softbench {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// The bench's geometry: a camera 475 mm above the dot plane, its foot at
// the origin; a head's three dots about 11 mm apart.
CameraAbovePlane Bench() { return {Eigen::Vector2d::Zero(), 475.0}; }

// A dot's standard error in an uncompressed picture, weighing the fits of
// exact or nearly exact dots.
constexpr double kStillDotSigmaMm = 0.001;

std::vector<Eigen::Vector2d> Dots(const Eigen::Vector2d& centre) {
  return {centre + Eigen::Vector2d(-5.5, -3.2),
          centre + Eigen::Vector2d(5.5, -3.2),
          centre + Eigen::Vector2d(0.0, 6.4)};
}

// The mean and standard deviation of the lifts fitted to `trials` copies
// of `seen`, each coordinate moved by normal noise of `sigma_mm`, the fits
// weighing the dots at `weighed_sigma_mm`.
std::array<double, 2> LiftMeanAndScatter(
    const std::vector<Eigen::Vector2d>& rest,
    const std::vector<Eigen::Vector2d>& seen, double sigma_mm, unsigned seed,
    int trials, double weighed_sigma_mm = kStillDotSigmaMm) {
  std::mt19937 rng(seed);
  // Scaled by hand: sigma_mm may be 0, which a distribution may not have.
  std::normal_distribution<double> noise;
  double sum = 0.0, sum2 = 0.0;
  for (int t = 0; t < trials; ++t) {
    std::vector<Eigen::Vector2d> noisy = seen;
    for (Eigen::Vector2d& d : noisy)
      d += sigma_mm * Eigen::Vector2d(noise(rng), noise(rng));
    const double lift =
        FitPlatePose(rest, noisy, Bench(), weighed_sigma_mm).lift_mm;
    sum += lift;
    sum2 += lift * lift;
  }
  const double mean = sum / trials;
  return {mean, std::sqrt(sum2 / trials - mean * mean)};
}

TEST(PlatePose, RestIsTheIdentity) {
  const std::vector<Eigen::Vector2d> rest = Dots({50, -20});
  const PlatePose pose = FitPlatePose(rest, rest, Bench(), kStillDotSigmaMm);
  ASSERT_TRUE(pose.found) << pose.why_not;
  EXPECT_NEAR(pose.lift_mm, 0.0, 1e-9);
  EXPECT_LT(pose.tilt_rad.norm(), 1e-9);
  EXPECT_LT(pose.parallax_mm.norm(), 1e-9);
  EXPECT_LT((pose.centre_mm - Eigen::Vector2d(50, -20)).norm(), 1e-9);
}

TEST(PlatePose, ALiftedPointShowsTheParallaxOfItsHeight) {
  // A flat plate raised by h: every dot at foot + (p - foot) H / (H - h).
  const std::vector<Eigen::Vector2d> rest = Dots({50, -20});
  const std::vector<Eigen::Vector2d> seen = ApparentDots(
      rest, Bench(), Eigen::Vector2d(50, -20), 0.6, Eigen::Vector2d::Zero(), 0);
  for (size_t i = 0; i < rest.size(); ++i) {
    EXPECT_LT((seen[i] - rest[i] * 475.0 / (475.0 - 0.6)).norm(), 1e-12);
  }
  // The example: 50 mm off the axis, 0.6 mm up looks like 0.063 mm.
  EXPECT_NEAR(
      (seen[0] + seen[1] + seen[2] - 3 * Eigen::Vector2d(50, -20)).norm() / 3,
      std::hypot(50, 20) * 0.6 / 474.4, 1e-12);
}

TEST(PlatePose, RecoversLiftTiltAndPositionOffTheAxis) {
  const std::vector<Eigen::Vector2d> rest = Dots({60, 25});
  for (const double lift : {0.0, 0.3, 0.6, -0.4}) {
    for (const Eigen::Vector2d& tilt :
         {Eigen::Vector2d(0, 0), Eigen::Vector2d(1 * kDeg, 0),
          Eigen::Vector2d(-0.6 * kDeg, 0.8 * kDeg)}) {
      const Eigen::Vector2d centre(61.2, 24.1);
      const PlatePose pose = FitPlatePose(
          rest, ApparentDots(rest, Bench(), centre, lift, tilt, 0.02), Bench(),
          kStillDotSigmaMm);
      ASSERT_TRUE(pose.found) << pose.why_not;
      // Exact data: only the tilt's prior pulls, and off the axis it
      // moves the lift by micrometres and the centre by less than one.
      EXPECT_NEAR(pose.lift_mm, lift, 5e-3) << tilt.transpose();
      EXPECT_LT((pose.tilt_rad - tilt).norm(), 2e-4);
      EXPECT_NEAR(pose.rotation_rad, 0.02, 1e-5);
      EXPECT_LT((pose.centre_mm - centre).norm(), 1e-3);
    }
  }
}

TEST(PlatePose, OnTheAxisTheLiftHoldsWhatTiltCannotShow) {
  // Straight below the camera a tilt shows only as foreshortening, to
  // second order: the lift must not take it for a change of scale.
  const std::vector<Eigen::Vector2d> rest = Dots({0.5, -0.3});
  const PlatePose pose =
      FitPlatePose(rest,
                   ApparentDots(rest, Bench(), Eigen::Vector2d(0.5, -0.3), 0.4,
                                Eigen::Vector2d(1 * kDeg, 0), 0),
                   Bench(), kStillDotSigmaMm);
  ASSERT_TRUE(pose.found);
  EXPECT_NEAR(pose.lift_mm, 0.4, 0.04);
  EXPECT_LT((pose.centre_mm - Eigen::Vector2d(0.5, -0.3)).norm(), 1e-3);
}

TEST(PlatePose, ConvergesNearTheAxisWithinItsDefaultIterations) {
  // Near the camera's foot a tilt shows only to second order, the fit
  // crawls along a valley of lift against tilt, and a fit stopped early
  // reads a lift that is the iteration budget's, not the dots' (30
  // iterations left the delta sample's lifts up to 0.07 mm off): the
  // default budget must reach the minimum that a ten times larger one does.
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.002);
  PlatePoseOptions patient;
  patient.max_iterations = 3000;
  const std::vector<Eigen::Vector2d> rest = Dots({1.0, 2.0});
  for (int t = 0; t < 200; ++t) {
    std::vector<Eigen::Vector2d> seen =
        ApparentDots(rest, Bench(), Eigen::Vector2d(1.3, 2.4), 0.1,
                     Eigen::Vector2d(0.5 * kDeg, -0.3 * kDeg), 0.01);
    for (Eigen::Vector2d& d : seen)
      d += Eigen::Vector2d(noise(rng), noise(rng));
    const PlatePose fast = FitPlatePose(rest, seen, Bench(), kStillDotSigmaMm);
    const PlatePose slow =
        FitPlatePose(rest, seen, Bench(), kStillDotSigmaMm, patient);
    ASSERT_TRUE(fast.found && slow.found) << fast.why_not << slow.why_not;
    EXPECT_NEAR(fast.lift_mm, slow.lift_mm, 1e-3) << t;
    EXPECT_LT((fast.tilt_rad - slow.tilt_rad).norm(), 1e-4) << t;
  }
}

TEST(PlatePose, LiftScatterFollowsTheDotsScatter) {
  // Dots with 0.0005 mm of noise (a few thousandths of a pixel): the lift
  // is found to the dots' relative precision times the camera's height.
  const std::vector<Eigen::Vector2d> rest = Dots({45, 30});
  const auto [mean, sd] =
      LiftMeanAndScatter(rest,
                         ApparentDots(rest, Bench(), Eigen::Vector2d(45, 30),
                                      0.5, Eigen::Vector2d::Zero(), 0),
                         0.0005, 7, 400);
  EXPECT_NEAR(mean, 0.5, 0.01);
  // About 0.0005 / 6 mm of relative spacing per dot, over 475 mm: ~0.04 mm;
  // well below 0.2 mm, and not zero.
  EXPECT_GT(sd, 0.005);
  EXPECT_LT(sd, 0.1);
}

TEST(PlatePose, LiftSigmaFromDotsIsTheLiftsScatter) {
  // Off the axis, where the tilts show and share the dots with the lift:
  // the propagated sigma against the scatter of fits to noisy dots.
  constexpr double kSigma = 0.002;
  const std::vector<Eigen::Vector2d> rest = Dots({45, 30});
  const double sd = LiftMeanAndScatter(rest, rest, kSigma, 11, 1000)[1];
  EXPECT_NEAR(LiftSigmaFromDots(rest, Bench(), kSigma, kStillDotSigmaMm), sd,
              0.08 * sd);
  // On the axis the lift is the dots' scale change alone: H sigma over the
  // root sum of their squared distances from their centre (11.04 mm).
  const std::vector<Eigen::Vector2d> on_axis = Dots({0, 0});
  EXPECT_NEAR(LiftSigmaFromDots(on_axis, Bench(), kSigma, kStillDotSigmaMm),
              475.0 * kSigma / std::sqrt(121.94), 0.002);
}

TEST(PlatePose, DotsWeighedAsTheyErrLeaveTheLiftUnbiasedNearTheAxis) {
  // A flat head near the camera's foot, its dots off by what a codec and a
  // phone's sharpening leave (0.02 px at 0.18 mm/px). Near the axis a tilt
  // shows only as foreshortening, which the lift makes up: a fit told the
  // dots are better than they are reads their errors as tilts and lifts
  // the plate; weighed as they err, its lift is their scale change alone.
  constexpr double kSigma = 0.0036;
  const std::vector<Eigen::Vector2d> rest = Dots({8, -5});
  const auto lifts = [&](double weighed_sigma_mm) {
    return LiftMeanAndScatter(rest, rest, kSigma, 13, 1000, weighed_sigma_mm);
  };
  const double propagated = LiftSigmaFromDots(rest, Bench(), kSigma, kSigma);
  const auto [mean, sd] = lifts(kSigma);
  // What is left is the fit's own: the tilts still follow the dots within
  // their prior (0.18 of the scatter here; none with the dots weighed at
  // twice their error).
  EXPECT_LT(std::abs(mean), 0.25 * propagated);
  EXPECT_NEAR(sd, propagated, 0.1 * propagated);
  // Told the dots are good to 0.001 mm (a still picture's precision), the
  // fit lifts the plate by about the lift's whole scatter, and scatters more.
  const auto [overconfident_mean, overconfident_sd] = lifts(kStillDotSigmaMm);
  EXPECT_GT(overconfident_mean, 0.75 * propagated);
  EXPECT_GT(overconfident_sd, 1.15 * propagated);
}

}  // namespace
}  // namespace softbench
