// The tag's image fitted whole (vision/tag_model.h, issue 28) on rendered
// 720p frames whose small cells let a phone's processing move the border's
// midlines: the fitted corners hold the scale where the midlines do not.
#include "vision/tag_model.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "pipelines/synthetic/scene_renderer.h"
#include "tests/support/drawn_tag.h"
#include "vision/tag_detector.h"

namespace softbench {
namespace {

// Mean distance of the corners from their centre [px].
double TagSize(const std::array<Eigen::Vector2d, 4>& corners) {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& c : corners) centre += c / 4.0;
  double size = 0.0;
  for (const Eigen::Vector2d& c : corners) size += (c - centre).norm() / 4.0;
  return size;
}

struct Scales {
  double midlines, model;  // size / truth - 1
  TagModelFit fit;
};

// A 720p frame (11.2 px cells) at a camera tilt, through a phone's S-curve
// and sharpening on the codes, measured both ways.
Scales MeasureAtTilt(double tilt_deg, double lens_blur_px) {
  const TestPlan plan = TagSevenPlan();
  RenderOptions options;
  options.intrinsics =
      CameraIntrinsics::FromEquivalentFocalLength(52.0, 1280, 720);
  options.noise_sigma_dn = options.shot_noise_dn = 0.0;
  options.lighting_gradient = options.vignetting = 0.0;
  options.tilt_x_deg = tilt_deg;
  options.tilt_y_deg = -0.6 * tilt_deg;
  options.lens_blur_px = lens_blur_px;
  options.tone_curve = 0.6;
  options.sharpen_radius_px = 1.5;
  options.sharpen_amount = 1.0;
  const SceneRenderer renderer(plan, options);
  cv::Mat luma;
  cv::cvtColor(renderer.Render({Eigen::Vector2d::Zero()}, 0), luma,
               cv::COLOR_BGR2GRAY);
  const std::vector<Eigen::Vector2d> truth_corners = renderer.TagCorners();
  const double truth = TagSize(
      {truth_corners[0], truth_corners[1], truth_corners[2], truth_corners[3]});
  const std::vector<TagDetection> tags = TagDetector().Detect(luma);
  EXPECT_EQ(tags.size(), 1u);
  if (tags.empty()) return {NAN, NAN, {}};
  Scales s;
  s.midlines = TagSize(tags[0].corners) / truth - 1.0;
  s.fit =
      FitTagModel(luma, Tag36h11Bitmap(7), tags[0].corners, TagModelOptions());
  s.model = TagSize(s.fit.corners) / truth - 1.0;
  return s;
}

TEST(FitTagModel, HoldsTheScaleOfSmallCellsThroughSharpening) {
  for (double blur : {0.0, 0.6}) {
    for (double tilt : {0.0, 0.35, 1.0, 2.0}) {
      const Scales s = MeasureAtTilt(tilt, blur);
      EXPECT_TRUE(s.fit.found) << s.fit.why_not;
      std::printf(
          "blur %.1f tilt %.2f: midlines %+.3f %%, model %+.4f %% (rms %.2f "
          "levels, %d px, %d iterations; blur %.2f, curve %.2f, sharpen "
          "%.2f x %.2f)\n",
          blur, tilt, 100 * s.midlines, 100 * s.model, s.fit.rms_levels,
          s.fit.pixels, s.fit.iterations, s.fit.lens_blur_px, s.fit.tone_curve,
          s.fit.sharpen_radius_px, s.fit.sharpen_amount);
      EXPECT_LT(std::abs(s.model), 5e-4) << blur << " " << tilt;
    }
  }
}

TEST(FitTagModel, SaysWhyItFoundNothing) {
  const TagBitmap bitmap = Tag36h11Bitmap(7);
  // Cells larger than the fit is for.
  const DrawnTag large = DrawTag(bitmap, 12, {240, 240}, {60, 60});
  TagModelOptions options;
  options.max_cell_px = 10.0;
  TagModelFit fit = FitTagModel(large.luma, bitmap, large.corners, options);
  EXPECT_FALSE(fit.found);
  EXPECT_NE(fit.why_not.find("more than 10"), std::string::npos) << fit.why_not;
  // The table around the tag cut off by the frame's edge.
  const DrawnTag edge = DrawTag(bitmap, 8, {120, 120}, {10, 20});
  fit = FitTagModel(edge.luma, bitmap, edge.corners, TagModelOptions());
  EXPECT_FALSE(fit.found);
  EXPECT_EQ(fit.why_not, "the tag and its margin leave the image");
  // One iteration: the model is evaluated, the solver not converged.
  const DrawnTag small = DrawTag(bitmap, 8, {160, 160}, {40, 40});
  options = TagModelOptions();
  options.max_iterations = 1;
  fit = FitTagModel(small.luma, bitmap, small.corners, options);
  EXPECT_FALSE(fit.found);
  EXPECT_NE(fit.why_not.find("did not converge"), std::string::npos)
      << fit.why_not;
  EXPECT_GT(fit.pixels, 0);
  EXPECT_EQ(fit.iterations, 2);  // the start and one step
}

TEST(FitTagModel, FindsTheCornersOfASharpTag) {
  const TagBitmap bitmap = Tag36h11Bitmap(7);
  const DrawnTag tag = DrawTag(bitmap, 8, {160, 160}, {40, 40});
  std::array<Eigen::Vector2d, 4> start = tag.corners;
  for (Eigen::Vector2d& c : start) c += Eigen::Vector2d(0.3, -0.2);
  const TagModelFit fit =
      FitTagModel(tag.luma, bitmap, start, TagModelOptions());
  ASSERT_TRUE(fit.found) << fit.why_not;
  for (int i = 0; i < 4; ++i) {
    EXPECT_LT((fit.corners[i] - tag.corners[i]).norm(), 0.02) << i;
  }
  EXPECT_LT(fit.rms_levels, 1.0);
}

}  // namespace
}  // namespace softbench
