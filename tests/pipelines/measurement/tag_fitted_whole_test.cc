// The plan's tag fitted whole against its border's midlines
// (pipelines/measurement/plan_camera.h): the scale taken from the fit, and
// when it is refused.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "pipelines/measurement/plan_camera.h"
#include "tests/support/drawn_tag.h"
#include "vision/tag_bitmap.h"

namespace softbench {
namespace {

// A tag seen in perspective: a square's corners through a homography.
std::array<Eigen::Vector2d, 4> TiltedCorners() {
  Eigen::Matrix3d h;
  h << 1.02, 0.05, 300, -0.03, 0.97, 200, 2e-4, -1e-4, 1;
  std::array<Eigen::Vector2d, 4> corners;
  const Eigen::Vector2d square[4] = {{0, 100}, {100, 100}, {100, 0}, {0, 0}};
  for (int i = 0; i < 4; ++i) {
    corners[i] = (h * square[i].homogeneous()).hnormalized();
  }
  return corners;
}

double Side(const std::array<Eigen::Vector2d, 4>& c, int from, int to) {
  return (c[to] - c[from]).norm();
}

TEST(ScaledTagCorners, LeavesTheCornersAtScaleOne) {
  const std::array<Eigen::Vector2d, 4> corners = TiltedCorners();
  const std::array<Eigen::Vector2d, 4> same =
      ScaledTagCorners(corners, Eigen::Vector2d::Ones());
  for (int i = 0; i < 4; ++i) {
    EXPECT_LT((same[i] - corners[i]).norm(), 1e-9) << i;
  }
}

TEST(ScaledTagCorners, ScalesEachAxisAndComesBack) {
  const std::array<Eigen::Vector2d, 4> corners = TiltedCorners();
  const Eigen::Vector2d scale(1.004, 0.997);
  const std::array<Eigen::Vector2d, 4> scaled =
      ScaledTagCorners(corners, scale);
  // Along the tag's x axis (corner 0 to 1, and 3 to 2) and its y axis; in
  // perspective the sides scale by nearly, not exactly, the factor.
  EXPECT_NEAR(Side(scaled, 0, 1) / Side(corners, 0, 1), scale.x(), 2e-4);
  EXPECT_NEAR(Side(scaled, 3, 2) / Side(corners, 3, 2), scale.x(), 2e-4);
  EXPECT_NEAR(Side(scaled, 0, 3) / Side(corners, 0, 3), scale.y(), 2e-4);
  EXPECT_NEAR(Side(scaled, 1, 2) / Side(corners, 1, 2), scale.y(), 2e-4);
  const std::array<Eigen::Vector2d, 4> back =
      ScaledTagCorners(scaled, scale.cwiseInverse());
  for (int i = 0; i < 4; ++i) {
    EXPECT_LT((back[i] - corners[i]).norm(), 1e-9) << i;
  }
}

TEST(FitTagWhole, AgreesWithTheMidlinesOnASharpTag) {
  const TestPlan plan = TagSevenPlan();
  const DrawnTag tag = DrawTag(Tag36h11Bitmap(7), 9, {200, 200}, {45, 45});
  const TagFittedWhole whole = FitTagWhole(plan, tag.luma, LumaEncoding(),
                                           tag.corners, TagModelOptions());
  ASSERT_TRUE(whole.fit.found) << whole.fit.why_not;
  EXPECT_NEAR(whole.scale.x(), 1.0, 2e-4);
  EXPECT_NEAR(whole.scale.y(), 1.0, 2e-4);
  EXPECT_NEAR(whole.ScaleChange(), 0.0, 2e-4);
}

TEST(FitTagWhole, RefusesAFitThatMovesTheScaleTooFar) {
  const TestPlan plan = TagSevenPlan();
  const DrawnTag tag = DrawTag(Tag36h11Bitmap(7), 9, {200, 200}, {45, 45});
  // No fit moves the midlines by exactly nothing.
  const TagFittedWhole whole = FitTagWhole(plan, tag.luma, LumaEncoding(),
                                           tag.corners, TagModelOptions(), 0.0);
  EXPECT_FALSE(whole.fit.found);
  EXPECT_NE(whole.fit.why_not.find("moved the scale"), std::string::npos)
      << whole.fit.why_not;
  EXPECT_EQ(whole.scale, Eigen::Vector2d::Ones());
  EXPECT_EQ(whole.ScaleChange(), 0.0);
}

TEST(FitTagWhole, SaysWhenTheFrameHasNoBorderToStartFrom) {
  const TestPlan plan = TagSevenPlan();
  const DrawnTag tag = DrawTag(Tag36h11Bitmap(7), 9, {200, 200}, {45, 45});
  const cv::Mat blank(tag.luma.size(), CV_8UC1, cv::Scalar(120));
  const TagFittedWhole whole =
      FitTagWhole(plan, blank, LumaEncoding(), tag.corners, TagModelOptions());
  EXPECT_FALSE(whole.fit.found);
  EXPECT_NE(whole.fit.why_not.find("midlines were not found"),
            std::string::npos)
      << whole.fit.why_not;
}

}  // namespace
}  // namespace softbench
