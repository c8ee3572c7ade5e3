// A rolling shutter's readout from the registration's per-frame sums
// (issue 28): generated frames of a trembling camera whose misfits carry
// the shear a known readout leaves, with noise.
#include "vision/rolling_shutter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace softbench {
namespace {

struct Clip : RegisteredFrames {
  RollingShutter Estimate(const RollingShutterOptions& options = {}) const {
    return EstimateRollingShutter(*this, ImageVelocities(*this, options),
                                  options);
  }
};

// `frames` at 30 fps of a camera trembling by `tremor_px` RMS per axis in
// tones from 2 to 12 Hz (a tripod's), read by a shutter of `rows_s` along
// the rows and `columns_s` along the columns; each frame's 20 static
// points give misfits of 0.02 px noise, and a shear pattern common to all
// frames (the reference frame's own) is added.
Clip Trembling(int frames, double tremor_px, double rows_s, double columns_s,
               uint32_t seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> phase(0.0, 2.0 * std::numbers::pi);
  constexpr int kTones = 6;
  std::vector<Eigen::Vector2d> phases;
  for (int k = 0; k < kTones; ++k)
    phases.emplace_back(phase(random), phase(random));
  const double amplitude = tremor_px * std::sqrt(2.0 / kTones);
  const Eigen::Vector4d common(0.03, -0.02, 0.01, 0.04);
  Clip clip;
  for (int i = 0; i < frames; ++i) {
    const double t = i / 30.0;
    Eigen::Vector2d shift = Eigen::Vector2d::Zero(), v = shift;
    for (int k = 0; k < kTones; ++k) {
      const double w = 2.0 * std::numbers::pi * (2.0 + 2.0 * k);
      for (int c = 0; c < 2; ++c) {
        shift[c] += amplitude * std::sin(w * t + phases[k][c]);
        v[c] += amplitude * w * std::cos(w * t + phases[k][c]);
      }
    }
    Eigen::Vector4d coefficients = common;
    coefficients.head<2>() += rows_s * v;
    coefficients.tail<2>() += columns_s * v;
    // Twenty points' bases: their lines' offsets times the unit moves.
    Eigen::Matrix<double, 40, 4> basis = Eigen::Matrix<double, 40, 4>::Zero();
    std::uniform_real_distribution<double> offset(-0.5, 0.5);
    for (int p = 0; p < 20; ++p) {
      const double row = offset(random), column = offset(random);
      for (int c = 0; c < 2; ++c) {
        basis(2 * p + c, c) = -row;
        basis(2 * p + c, 2 + c) = -column;
      }
    }
    Eigen::Matrix<double, 40, 1> misfit = basis * coefficients;
    for (int r = 0; r < 40; ++r) misfit[r] += 0.02 * normal(random);
    clip.times_s.push_back(t);
    clip.shifts_px.push_back(shift);
    clip.sums.push_back(
        {basis.transpose() * misfit, basis.transpose() * basis});
    clip.index.push_back(i);
    clip.registered.push_back(true);
  }
  return clip;
}

TEST(RollingShutter, RecoversAReadoutAlongTheRowsOrTheColumns) {
  const RollingShutter rows = Trembling(300, 0.1, 0.025, 0.0, 1).Estimate();
  ASSERT_TRUE(rows.measured) << rows.why_not;
  EXPECT_TRUE(rows.seen);
  EXPECT_TRUE(rows.by_rows);
  // The tremor's 12 Hz tone too: a central difference would read its
  // velocity short and the readout long by tens of per cent.
  EXPECT_NEAR(rows.rows_readout_s, 0.025, 0.0005);
  EXPECT_NEAR(rows.columns_readout_s, 0.0, 4 * rows.columns_standard_error_s);
  EXPECT_NE(rows.Summary().find("top row first"), std::string::npos)
      << rows.Summary();
  // A portrait video's sensor reads the upright picture's columns, here
  // from the right.
  const RollingShutter columns = Trembling(300, 0.1, 0.0, -0.015, 2).Estimate();
  ASSERT_TRUE(columns.measured) << columns.why_not;
  EXPECT_TRUE(columns.seen);
  EXPECT_FALSE(columns.by_rows);
  EXPECT_NEAR(columns.readout_s(), -0.015, 0.0005);
  EXPECT_NE(columns.Summary().find("right column first"), std::string::npos)
      << columns.Summary();
  // The shear: the readout times the image's speed, RMS. The tremor's
  // speed is sqrt(2) x 0.1 px x its tones' RMS angular frequency.
  const double speed_px_s =
      0.1 * 2.0 * std::numbers::pi *
      std::sqrt((4 + 16 + 36 + 64 + 100 + 144) / 6.0 * 2.0);
  EXPECT_NEAR(rows.shear_rms_px, 0.025 * speed_px_s, 0.05 * 0.025 * speed_px_s);
}

// The standard error is the readout's: over many clips the errors scatter
// by about it, and within three of it nearly always.
TEST(RollingShutter, StandardErrorCoversTheReadoutsError) {
  int within = 0;
  double squares = 0.0, errors = 0.0;
  constexpr int kClips = 40;
  for (uint32_t seed = 10; seed < 10 + kClips; ++seed) {
    // A tremor small enough that the noise matters, every readout kept.
    RollingShutterOptions options;
    options.max_standard_error_s = 1.0;
    options.systematic_s = 0.0;
    const RollingShutter r =
        Trembling(300, 0.01, 0.02, 0.0, seed).Estimate(options);
    ASSERT_TRUE(r.measured) << r.why_not;
    const double error = r.rows_readout_s - 0.02;
    if (std::abs(error) <= 3.0 * r.rows_standard_error_s) ++within;
    squares += error * error;
    errors += r.rows_standard_error_s * r.rows_standard_error_s;
  }
  EXPECT_GE(within, kClips - 2);
  const double ratio = std::sqrt(squares / errors);
  EXPECT_GT(ratio, 0.6);
  EXPECT_LT(ratio, 1.5);
}

TEST(RollingShutter, AGlobalShutterIsMeasuredButNotSeen) {
  const RollingShutter r = Trembling(300, 0.1, 0.0, 0.0, 3).Estimate();
  ASSERT_TRUE(r.measured) << r.why_not;
  EXPECT_FALSE(r.seen);
  EXPECT_LT(std::abs(r.rows_readout_s), 0.001);
  EXPECT_NE(r.Summary().find("none seen"), std::string::npos) << r.Summary();
}

// A still camera's image does not move, so no shear shows: not measured,
// rather than "none".
TEST(RollingShutter, AStillCameraIsNotMeasured) {
  const RollingShutter r = Trembling(300, 1e-5, 0.03, 0.0, 4).Estimate();
  EXPECT_FALSE(r.measured);
  EXPECT_NE(r.why_not.find("moved too little"), std::string::npos) << r.why_not;
}

// Velocities come only from registered, consecutive, evenly spaced frames:
// a clip cut into short runs by dropped frames has too few.
TEST(RollingShutter, NeedsRunsOfRegisteredConsecutiveFrames) {
  Clip clip = Trembling(300, 0.1, 0.025, 0.0, 5);
  for (size_t i = 0; i < clip.index.size(); ++i) {
    if (i % 12 == 11) clip.registered[i] = false;
  }
  RollingShutter r = clip.Estimate();
  EXPECT_FALSE(r.measured);
  EXPECT_EQ(r.frames, 0);
  // Dropped frames (indices skipped, times kept evenly spaced or not) and
  // uneven times do the same.
  clip = Trembling(300, 0.1, 0.025, 0.0, 5);
  for (size_t i = 0; i < clip.index.size(); ++i) {
    clip.index[i] += static_cast<int64_t>(i / 12);
  }
  EXPECT_EQ(clip.Estimate().frames, 0);
  clip = Trembling(300, 0.1, 0.025, 0.0, 5);
  for (size_t i = 0; i < clip.times_s.size(); ++i) {
    if (i % 12 == 11) clip.times_s[i] += 0.5 / 30.0;
  }
  EXPECT_EQ(clip.Estimate().frames, 0);
  // One dropped frame costs the frames within 8 of it only.
  clip = Trembling(300, 0.1, 0.025, 0.0, 5);
  clip.registered[150] = false;
  r = clip.Estimate();
  EXPECT_EQ(r.frames, 300 - 16 - 17);
  EXPECT_TRUE(r.seen);
}

// A line's delay runs from minus half the readout at the first line to
// plus half at the last, along the shutter's lines; nothing when unseen.
TEST(RollingShutter, ReadsEachLineAtItsOwnDelay) {
  RollingShutter r;
  r.rows_readout_s = 0.02;
  const Eigen::Vector2d size(1920, 1080);
  EXPECT_EQ(r.ReadDelayS({960, 0}, size), 0.0);
  r.seen = true;
  EXPECT_NEAR(r.ReadDelayS({5, -0.5}, size), -0.01, 1e-12);
  EXPECT_NEAR(r.ReadDelayS({1900, 539.5}, size), 0.0, 1e-12);
  EXPECT_NEAR(r.ReadDelayS({0, 1079.5}, size), 0.01, 1e-12);
  r.by_rows = false;
  r.columns_readout_s = -0.03;
  EXPECT_NEAR(r.ReadDelayS({1919.5, 0}, size), -0.015, 1e-12);
}

// The middle line's motion undoes what the fit took up of the shear: the
// fitted parameters less motion_from_basis times the shear's coefficients
// (the readout times the velocity on the shutter's two bases).
TEST(RollingShutter, MiddleLineMotionTakesBackWhatTheFitTookUp) {
  ShutterShearSums sums;
  sums.motion_from_basis << 1, 2, 3, 4,  //
      5, 6, 7, 8,                        //
      9, 10, 11, 12,                     //
      13, 14, 15, 16;
  sums.motion_from_basis *= 1e-4;
  CameraMotion fitted;
  fitted.rotation_rad = {1e-3, -2e-3, 5e-4};
  fitted.scale = 1.001;
  const Eigen::Vector2d v(10.0, -4.0);
  RollingShutter r;
  EXPECT_EQ(r.MiddleLineMotion(fitted, sums, v).rotation_rad,
            fitted.rotation_rad);
  r.seen = true;
  r.rows_readout_s = 0.025;
  for (const bool rows : {true, false}) {
    r.by_rows = rows;
    r.columns_readout_s = rows ? 0.0 : 0.025;
    Eigen::Vector4d coefficients = Eigen::Vector4d::Zero();
    coefficients.segment<2>(rows ? 0 : 2) = 0.025 * v;
    const Eigen::Vector4d taken = sums.motion_from_basis * coefficients;
    const CameraMotion middle = r.MiddleLineMotion(fitted, sums, v);
    EXPECT_LT(
        (middle.rotation_rad - (fitted.rotation_rad - taken.head<3>())).norm(),
        1e-15);
    EXPECT_NEAR(std::log(middle.scale), std::log(fitted.scale) - taken[3],
                1e-15);
  }
}

TEST(RollingShutterOptions, ProblemNamesTheBadField) {
  EXPECT_FALSE(RollingShutterOptions{}.Problem());
  RollingShutterOptions o;
  o.velocity_half_frames = 0;
  EXPECT_NE(o.Problem()->find("velocity_half_frames"), std::string::npos);
  o = {};
  o.min_blocks = 1;
  EXPECT_NE(o.Problem()->find("min_blocks"), std::string::npos);
  o = {};
  o.max_standard_error_s = 0.0;
  EXPECT_NE(o.Problem()->find("max_standard_error_s"), std::string::npos);
}

}  // namespace
}  // namespace softbench
