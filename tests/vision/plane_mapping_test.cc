#include "vision/plane_mapping.h"

#include <gtest/gtest.h>

#include <numbers>

namespace softbench {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// The tag's corners as a camera sees them (libapriltag's order).
std::array<Eigen::Vector2d, 4> TagCorners(const Camera& camera, double size) {
  const double h = size / 2;
  return {camera.Project({-h, -h, 0}), camera.Project({h, -h, 0}),
          camera.Project({h, h, 0}), camera.Project({-h, h, 0})};
}

TEST(PlaneMapping, TagGivesTheDotPlaneOfATiltedDistortedCamera) {
  CameraIntrinsics k =
      CameraIntrinsics::FromEquivalentFocalLength(52, 1920, 1080);
  k.distortion = {-0.1, 0.02, 0.0005, -0.0003, 0.0};
  const Camera camera =
      Camera::LookingDown(k, {40, 30, 16}, 490, 5 * kDeg, -3 * kDeg);
  const PlaneMapping mapping =
      PlaneMapping::FromTag(k, TagCorners(camera, 25), 25, 16);
  for (const Eigen::Vector2d& p :
       {Eigen::Vector2d(40, 30), Eigen::Vector2d(55, 20),
        Eigen::Vector2d(-10, 60)}) {
    const Eigen::Vector2d pixel = camera.Project({p.x(), p.y(), 16});
    EXPECT_LT((mapping.ToPlane(pixel) - p).norm(), 1e-6) << p.transpose();
    EXPECT_LT((mapping.ToPixel(p) - pixel).norm(), 1e-6);
  }
  // The tilt the pose corrects: 5 deg about x after -3 deg about y.
  EXPECT_NEAR(mapping.TiltRad(),
              std::acos(std::cos(5 * kDeg) * std::cos(3 * kDeg)), 1e-6);
  // The camera's height above the tag, from the tag's pose alone: 490 mm
  // along the tilted axis from a point 16 mm above the tag.
  EXPECT_NEAR(mapping.CameraHeightMm(),
              16 + 490 * std::cos(5 * kDeg) * std::cos(3 * kDeg), 1e-6);
  // A point on the tag plane is not on the dot plane: the offset matters.
  const Eigen::Vector2d low = mapping.ToPlane(camera.Project({40, 30, 0}));
  EXPECT_GT((low - Eigen::Vector2d(40, 30)).norm(), 0.5);
}

TEST(PlaneMapping, ScaleAndRotationFollowTheImage) {
  const CameraIntrinsics k =
      CameraIntrinsics::FromEquivalentFocalLength(52, 1920, 1080);
  const PlaneMapping plain = PlaneMapping::FromScale(k, 0.2, 0.0);
  const Eigen::Vector2d centre(959.5, 539.5);
  // Image right is +y, image up (smaller v) is +z.
  EXPECT_LT((plain.ToPlane(centre + Eigen::Vector2d(10, 0)) -
             plain.ToPlane(centre) - Eigen::Vector2d(2, 0))
                .norm(),
            1e-12);
  EXPECT_LT((plain.ToPlane(centre + Eigen::Vector2d(0, -10)) -
             plain.ToPlane(centre) - Eigen::Vector2d(0, 2))
                .norm(),
            1e-12);
  EXPECT_NEAR(plain.MmPerPixelAt(centre), 0.2, 1e-12);
  EXPECT_EQ(plain.TiltRad(), 0.0);
  // Turned 90 deg counter-clockwise: world +y points up the image.
  const PlaneMapping turned = PlaneMapping::FromScale(k, 0.2, 90 * kDeg);
  EXPECT_LT((turned.ToPlane(centre + Eigen::Vector2d(0, -10)) -
             turned.ToPlane(centre) - Eigen::Vector2d(2, 0))
                .norm(),
            1e-9);
}

}  // namespace
}  // namespace softbench
