#include "vision/tag_detector.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <numbers>
#include <random>

#include "vision/camera.h"
#include "vision/plane_mapping.h"

namespace softbench {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
using Corners = std::array<Eigen::Vector2d, 4>;

// A 25 mm tag as a camera 0.3 deg off square sees it from 490 mm.
struct TiltedTag {
  CameraIntrinsics k =
      CameraIntrinsics::FromEquivalentFocalLength(52, 1920, 1080);
  Camera camera = Camera::LookingDown(k, {40, 30, 0}, 490, 0.3 * kDeg, 0.0);
  Corners corners = {
      camera.Project({-12.5, -12.5, 0}), camera.Project({12.5, -12.5, 0}),
      camera.Project({12.5, 12.5, 0}), camera.Project({-12.5, 12.5, 0})};
  double TiltOf(const Corners& c) const {
    return PlaneMapping::FromTag(k, c, 25, 0).TiltRad();
  }
};

// `corners` turned by `roll` about their first corner and shifted.
Corners Moved(const Corners& corners, double roll, const Eigen::Vector2d& by) {
  Corners out;
  for (int c = 0; c < 4; ++c) {
    out[c] =
        corners[0] + Eigen::Rotation2Dd(roll) * (corners[c] - corners[0]) + by;
  }
  return out;
}

TEST(AverageTagCorners, UndoesEachFramesShiftAndRollExactly) {
  const TiltedTag tag;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> shift(-2.0, 2.0), roll(-0.1, 0.1);
  std::vector<Corners> frames;
  for (int f = 0; f < 50; ++f) {
    frames.push_back(Moved(tag.corners, roll(rng) * kDeg,
                           Eigen::Vector2d(shift(rng), shift(rng))));
  }
  const Corners average = AverageTagCorners(tag.corners, frames);
  for (int c = 0; c < 4; ++c) {
    EXPECT_LT((average[c] - tag.corners[c]).norm(), 1e-9) << c;
  }
}

TEST(AverageTagCorners, FindsTheTiltThatOneFrameCannot) {
  // Corners off by 0.03 px in each frame (a codec's error at 1080p) on a
  // camera that shakes by pixels and hundredths of a degree.
  const TiltedTag tag;
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.03), shift(0.0, 1.0),
      roll(0.0, 0.03 * kDeg);
  std::vector<Corners> frames;
  for (int f = 0; f < 400; ++f) {
    Corners c =
        Moved(tag.corners, roll(rng), Eigen::Vector2d(shift(rng), shift(rng)));
    for (Eigen::Vector2d& corner : c) {
      corner += Eigen::Vector2d(noise(rng), noise(rng));
    }
    frames.push_back(c);
  }
  const double truth = tag.TiltOf(tag.corners);
  EXPECT_NEAR(truth, 0.3 * kDeg, 1e-6);
  // One frame's tilt is off by a tenth of a degree or so; the average of
  // the frames, registered to the first, by a hundredth.
  double worst_single = 0.0;
  for (int f = 0; f < 10; ++f) {
    worst_single =
        std::max(worst_single, std::abs(tag.TiltOf(frames[f]) - truth));
  }
  EXPECT_GT(worst_single, 0.05 * kDeg);
  const Corners average = AverageTagCorners(frames.front(), frames);
  EXPECT_LT(std::abs(tag.TiltOf(average) - truth), 0.02 * kDeg);
}

}  // namespace
}  // namespace softbench
