// The uncertainty budget's intrinsics term (plan_camera.h's
// IntrinsicsSensitivity): what a calibration one standard error off does to
// a measured change, each parameter's share in quadrature, linear in the
// standard errors.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>

#include "pipelines/formats/test_plan.h"
#include "pipelines/measurement/plan_camera.h"
#include "vision/camera.h"
#include "vision/plane_mapping.h"

namespace softbench {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kTagMm = 25.0, kPlaneMm = 16.0;

TestPlan PlanWith(const std::string& calibration) {
  return ParseTestPlan(
      "mechanism: delta\npressure_unit: psi\ncalibration: " + calibration +
          "\ntests:\n  - {id: a, pressures: [6, 6, 0]}\n",
      "plan.yaml");
}

TestPlan TagPlan() {
  return PlanWith(
      "{tag: {family: tag36h11, id: 0, size_mm: 25}, plane_offset_mm: 16}");
}

// A phone's lens (barrel distortion) 490 mm above the bench, tilted, as
// the true camera; the tag's corners as it sees them.
struct Bench {
  CameraIntrinsics truth = [] {
    CameraIntrinsics k =
        CameraIntrinsics::FromEquivalentFocalLength(26, 1920, 1080);
    k.distortion = {-0.12, 0.03, 4e-4, -3e-4, 0.0};
    return k;
  }();
  Camera camera =
      Camera::LookingDown(truth, {0, 0, kPlaneMm}, 490, 4 * kDeg, -2 * kDeg);
  std::array<Eigen::Vector2d, 4> corners = [this] {
    const double h = kTagMm / 2;
    return std::array<Eigen::Vector2d, 4>{
        camera.Project({-h, -h, 0}), camera.Project({h, -h, 0}),
        camera.Project({h, h, 0}), camera.Project({-h, h, 0})};
  }();
  // A head far out in the field, where the lens bends most, moving 2 mm.
  Eigen::Vector2d from_mm{150.0, 70.0}, to_mm{151.6, 68.8};

  Eigen::Vector2d Pixel(const Eigen::Vector2d& p) const {
    return camera.Project({p.x(), p.y(), kPlaneMm});
  }
};

// A calibration whose k1 is one standard error short of the truth measures
// the head's change wrong by what the term says (to the second order in
// the standard error: the term is the change's slope in k1 times it).
TEST(IntrinsicsSensitivity, IsTheErrorOfACalibrationOneStandardErrorOff) {
  const Bench bench;
  CameraIntrinsics calibrated = bench.truth;
  calibrated.distortion_std[0] = 0.004;
  calibrated.distortion[0] -= calibrated.distortion_std[0];
  const PlaneMapping mapping =
      PlaneMapping::FromTag(calibrated, bench.corners, kTagMm, kPlaneMm);
  const Eigen::Vector2d from = mapping.ToPlane(bench.Pixel(bench.from_mm));
  const Eigen::Vector2d to = mapping.ToPlane(bench.Pixel(bench.to_mm));
  const Eigen::Vector2d error = (to - from) - (bench.to_mm - bench.from_mm);
  // The error is worth a term: a few microns on a 2 mm change.
  ASSERT_GT(error.norm(), 5e-4);
  const IntrinsicsSensitivity sensitivity(TagPlan(), calibrated, mapping,
                                          bench.corners);
  ASSERT_TRUE(sensitivity.Known());
  const Eigen::Vector2d u = sensitivity.ChangeUncertaintyMm(from, to);
  EXPECT_NEAR(u.x(), std::abs(error.x()), 0.03 * error.norm());
  EXPECT_NEAR(u.y(), std::abs(error.y()), 0.03 * error.norm());
}

// Every parameter's share adds in quadrature, and the term is linear in
// the standard errors.
TEST(IntrinsicsSensitivity,
     AddsParametersInQuadratureAndScalesWithTheirErrors) {
  const Bench bench;
  CameraIntrinsics k = bench.truth;
  k.intrinsics_std_px = {1.0, 0.9, 0.8, 0.7};
  k.distortion_std = {0.002, 0.006, 5e-5, 5e-5, 0.01};
  const PlaneMapping mapping =
      PlaneMapping::FromTag(k, bench.corners, kTagMm, kPlaneMm);
  const auto term = [&](const CameraIntrinsics& with) {
    return IntrinsicsSensitivity(TagPlan(), with, mapping, bench.corners)
        .ChangeUncertaintyMm(bench.from_mm, bench.to_mm);
  };
  const Eigen::Vector2d all = term(k);
  Eigen::Vector2d squares = Eigen::Vector2d::Zero();
  for (int i = 0; i < 9; ++i) {
    CameraIntrinsics one = k;
    one.intrinsics_std_px.fill(0.0);
    one.distortion_std.fill(0.0);
    if (i < 4) {
      one.intrinsics_std_px[i] = k.intrinsics_std_px[i];
    } else {
      one.distortion_std[i - 4] = k.distortion_std[i - 4];
    }
    const Eigen::Vector2d u = term(one);
    EXPECT_GT(u.norm(), 0.0) << "parameter " << i << " has no effect";
    squares += u.array().square().matrix();
  }
  EXPECT_NEAR(all.x(), std::sqrt(squares.x()), 1e-12);
  EXPECT_NEAR(all.y(), std::sqrt(squares.y()), 1e-12);
  // Halved, the term halves (to within the curvature of the tag's pose in
  // the focal length, which a 25 mm tag 150 mm from the head shows).
  CameraIntrinsics halved = k;
  for (double& s : halved.intrinsics_std_px) s *= 0.5;
  for (double& s : halved.distortion_std) s *= 0.5;
  const Eigen::Vector2d half = term(halved);
  EXPECT_NEAR(half.x(), 0.5 * all.x(), 0.05 * all.norm());
  EXPECT_NEAR(half.y(), 0.5 * all.y(), 0.05 * all.norm());
}

// Without standard errors (a file from OpenCV's own tools, or no
// intrinsics) there is no term; with a scale instead of a tag, the lens's
// errors still bend a change far from the centre.
TEST(IntrinsicsSensitivity, NeedsStandardErrorsAndWorksWithAScale) {
  const Bench bench;
  const PlaneMapping tag =
      PlaneMapping::FromTag(bench.truth, bench.corners, kTagMm, kPlaneMm);
  const IntrinsicsSensitivity none(TagPlan(), bench.truth, tag, bench.corners);
  EXPECT_FALSE(none.Known());
  EXPECT_EQ(none.ChangeUncertaintyMm(bench.from_mm, bench.to_mm).norm(), 0.0);
  EXPECT_FALSE(IntrinsicsSensitivity().Known());

  CameraIntrinsics k = bench.truth;
  k.distortion_std[0] = 0.004;
  const TestPlan scale_plan = PlanWith("{mm_per_px: 0.2}");
  const PlaneMapping scale = PlaneMapping::FromScale(k, 0.2, 0.0);
  const IntrinsicsSensitivity sensitivity(scale_plan, k, scale, std::nullopt);
  ASSERT_TRUE(sensitivity.Known());
  const Eigen::Vector2d far =
      sensitivity.ChangeUncertaintyMm(bench.from_mm, bench.to_mm);
  const Eigen::Vector2d centre = sensitivity.ChangeUncertaintyMm(
      Eigen::Vector2d::Zero(), bench.to_mm - bench.from_mm);
  EXPECT_GT(far.norm(), 1e-4);
  EXPECT_GT(far.norm(), 10.0 * centre.norm());
}

}  // namespace
}  // namespace softbench
