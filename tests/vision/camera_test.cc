#include "vision/camera.h"

#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <random>

#include "model/units.h"

namespace softbench {
namespace {

CameraIntrinsics Distorted() {
  CameraIntrinsics k =
      CameraIntrinsics::FromEquivalentFocalLength(52, 1920, 1080);
  k.distortion = {-0.1, 0.05, 0.001, -0.0015, -0.01};
  return k;
}

TEST(CameraIntrinsics, ThesisCameraGivesAbout0p18MmPerPixel) {
  const CameraIntrinsics k =
      CameraIntrinsics::FromEquivalentFocalLength(52, 1920, 1080);
  EXPECT_NEAR(k.fx_px, 2647.0, 1.0);
  EXPECT_NEAR(475.0 / k.fx_px, 0.179, 0.001);  // the issue's ~0.17 mm/px
  EXPECT_DOUBLE_EQ(k.cx_px, 959.5);
  EXPECT_FALSE(k.Problem().has_value());
}

TEST(Camera, ProjectionMatchesOpenCvProjectPoints) {
  const Camera camera = Camera::LookingDown(
      Distorted(), Eigen::Vector3d(3, -2, 16), 475, DegToRad(5), DegToRad(-3));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> xy(-150, 150), z(-10, 30);
  std::vector<cv::Point3d> points;
  std::vector<Eigen::Vector2d> ours;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p(xy(rng), xy(rng) * 0.6, z(rng));
    points.emplace_back(p.x(), p.y(), p.z());
    ours.push_back(camera.Project(p));
  }
  cv::Mat rotation, rvec;
  cv::eigen2cv(Eigen::Matrix3d(camera.camera_from_world()), rotation);
  cv::Rodrigues(rotation, rvec);
  const cv::Vec3d tvec(camera.translation().x(), camera.translation().y(),
                       camera.translation().z());
  std::vector<cv::Point2d> theirs;
  cv::projectPoints(points, rvec, tvec, camera.intrinsics().CameraMatrix(),
                    camera.intrinsics().distortion, theirs);
  for (size_t i = 0; i < theirs.size(); ++i) {
    EXPECT_NEAR(ours[i].x(), theirs[i].x, 1e-7);
    EXPECT_NEAR(ours[i].y(), theirs[i].y, 1e-7);
  }
}

TEST(Camera, UndistortInvertsDistortAcrossTheFrame) {
  const Camera camera(Distorted(), Eigen::Matrix3d::Identity(),
                      Eigen::Vector3d::Zero());
  for (double x = -0.4; x <= 0.4; x += 0.1) {
    for (double y = -0.2; y <= 0.2; y += 0.1) {
      const Eigen::Vector2d n(x, y);
      EXPECT_LT((camera.Undistort(camera.Distort(n)) - n).norm(), 1e-12);
    }
  }
}

TEST(Camera, LookingDownKeepsTheTargetCentredAndAxesUpright) {
  const CameraIntrinsics k =
      CameraIntrinsics::FromEquivalentFocalLength(52, 1920, 1080);
  const Eigen::Vector3d target(10, 20, 16);
  for (double tilt : {0.0, 5.0}) {
    const Camera camera =
        Camera::LookingDown(k, target, 475, DegToRad(tilt), 0);
    const Eigen::Vector2d c = camera.Project(target);
    EXPECT_NEAR(c.x(), k.cx_px, 1e-9);
    EXPECT_NEAR(c.y(), k.cy_px, 1e-9);
    // World +y (mechanism) is image right, world +z is image up.
    EXPECT_GT(camera.Project(target + Eigen::Vector3d(1, 0, 0)).x(), c.x());
    EXPECT_LT(camera.Project(target + Eigen::Vector3d(0, 1, 0)).y(), c.y());
  }
}

}  // namespace
}  // namespace softbench
