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

// A distorted camera 490 mm from a point 16 mm above a 25 mm tag, tilted
// 5 deg about x after -3 deg about y, and the dot plane's mapping from it.
struct TiltedBench {
  CameraIntrinsics k = [] {
    CameraIntrinsics k =
        CameraIntrinsics::FromEquivalentFocalLength(52, 1920, 1080);
    k.distortion = {-0.1, 0.02, 0.0005, -0.0003, 0.0};
    return k;
  }();
  Camera camera =
      Camera::LookingDown(k, {40, 30, 16}, 490, 5 * kDeg, -3 * kDeg);
  PlaneMapping mapping =
      PlaneMapping::FromTag(k, TagCorners(camera, 25), 25, 16);
};

TEST(PlaneMapping, TagGivesTheDotPlaneOfATiltedDistortedCamera) {
  const TiltedBench bench;
  const Camera& camera = bench.camera;
  const PlaneMapping& mapping = bench.mapping;
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

TEST(PlaneMapping, CameraAboveGivesTheParallaxOfARaisedPoint) {
  const TiltedBench bench;
  const Camera& camera = bench.camera;
  const PlaneMapping& mapping = bench.mapping;
  const CameraAbovePlane above = mapping.CameraAbove();
  EXPECT_NEAR(above.height_mm, mapping.CameraHeightMm() - 16, 1e-6);
  // A point straight below the centre shows no parallax when raised.
  for (const double lift : {0.6, 3.0, -2.0}) {
    for (const Eigen::Vector2d& p :
         {Eigen::Vector2d(90, 30), Eigen::Vector2d(40, -20), above.foot_mm}) {
      const Eigen::Vector2d seen =
          mapping.ToPlane(camera.Project({p.x(), p.y(), 16 + lift}));
      const Eigen::Vector2d expected =
          above.foot_mm +
          (p - above.foot_mm) * above.height_mm / (above.height_mm - lift);
      EXPECT_LT((seen - expected).norm(), 1e-6) << p.transpose();
    }
  }
  // From a scale: a fronto-parallel camera fx mm_per_px above the plane
  // point at the principal point.
  const CameraIntrinsics& k = bench.k;
  const PlaneMapping scaled = PlaneMapping::FromScale(k, 0.2, 0.3);
  EXPECT_NEAR(scaled.CameraAbove().height_mm, 0.2 * k.fx_px, 1e-9);
  EXPECT_LT((scaled.CameraAbove().foot_mm -
             scaled.ToPlane(Eigen::Vector2d(k.cx_px, k.cy_px)))
                .norm(),
            1e-9);
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
