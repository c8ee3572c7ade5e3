// The dots' spacing against the plan's layout (issue 28: when it and the
// tag disagree, which to trust): generated frames of one head whose dots
// are the plan's layout scaled, reshaped or scattered.
#include "pipelines/measurement/distortion_check.h"

#include <gtest/gtest.h>

#include <iostream>
#include <random>

#include "pipelines/formats/test_plan.h"

namespace softbench {
namespace {

TestPlan Plan(const std::string& layout) {
  return ParseTestPlan(R"(mechanism: delta
pressure_unit: psi
calibration:
  tag: {family: tag36h11, id: 0, size_mm: 25}
  plane_offset_mm: 16
markers:
  - {head: head, color: red, dots: 3, dot_diameter_mm: 4, layout_mm: )" +
                           layout + R"(}
tests:
  - {id: a, pressures: [1, 1, 1]}
)",
                       "plan.yaml");
}

const char kLayout[] = "[[0, 6.35], [-5.5, -3.175], [5.5, -3.175]]";

// 200 frames of the head with its dots at `dots_mm` times `scale`, plus
// from -`swing` over the first frame to +`swing` over the last (a lens's
// scale, different where the head moves), moved about and scattered by
// 0.002 mm per axis (a codec's noise).
std::vector<FrameSample> Frames(const std::vector<Eigen::Vector2d>& dots_mm,
                                double scale, double swing = 0.0) {
  std::mt19937 random(7);
  std::normal_distribution<double> noise(0.0, 0.002);
  std::uniform_real_distribution<double> place(-3.0, 3.0);
  std::vector<FrameSample> frames(200);
  for (size_t i = 0; i < frames.size(); ++i) {
    FrameSample& f = frames[i];
    const double frame_scale =
        scale + swing * (2.0 * i / (frames.size() - 1.0) - 1.0);
    HeadObservation o;
    o.complete = true;
    const Eigen::Vector2d at(place(random), place(random));
    for (const Eigen::Vector2d& d : dots_mm) {
      DotObservation dot;
      dot.found = true;
      dot.plane_mm =
          at + frame_scale * d + Eigen::Vector2d(noise(random), noise(random));
      o.dots.push_back(dot);
    }
    f.heads.push_back({o, {}, {}});
  }
  return frames;
}

// The camera 475 mm above the tag: the dots 459 mm from it.
constexpr double kCameraHeightMm = 475.0;

TEST(DistortionCheck, AgreesWithTheLayoutItsDotsHave) {
  const TestPlan plan = Plan(kLayout);
  const DistortionCheck check =
      CheckDistortion(plan, Frames(plan.markers[0].layout_mm, 1.0), "tag 0",
                      kCameraHeightMm, {});
  ASSERT_TRUE(check.performed);
  EXPECT_FALSE(check.warn) << check.message;
  EXPECT_NEAR(check.median_ratio, 1.0, 1e-4);
  EXPECT_EQ(check.shape_head, 0);
  EXPECT_LT(check.shape_misfit, 2e-4);
  EXPECT_NEAR(check.implied_plane_offset_mm, 16.0, 0.1);
}

// Dots 1.5 mm lower than plane_offset_mm says look 0.33 % small through
// the tag's mapping at 16 mm: the shape is the layout's, so the check names
// the height it implies (and a print's size) and keeps the tag.
TEST(DistortionCheck, NamesTheHeightAndPrintsWhenTheShapeFits) {
  const TestPlan plan = Plan(kLayout);
  const double scale = 459.0 / 460.5;
  const DistortionCheck check =
      CheckDistortion(plan, Frames(plan.markers[0].layout_mm, scale), "tag 0",
                      kCameraHeightMm, {});
  ASSERT_TRUE(check.warn) << check.message;
  std::cout << check.message << "\n";
  EXPECT_NEAR(check.implied_plane_offset_mm, 14.5, 0.05);
  EXPECT_LT(check.shape_misfit, 2e-4);
  for (const char* named :
       {"as if 14.5 mm", "plane_offset_mm says 16", "as if 25.08 mm",
        "cannot trace to one of", "tag 0 scale is kept"}) {
    EXPECT_NE(check.message.find(named), std::string::npos)
        << named << " in " << check.message;
  }
  EXPECT_EQ(check.message.find("layout_mm does not describe"),
            std::string::npos)
      << check.message;
  // Without calibration.intrinsics the lens is among the causes; a mapping
  // from a scale has no height to name.
  EXPECT_NE(check.message.find("the lens, uncalibrated"), std::string::npos);
  const DistortionCheck scaled = CheckDistortion(
      plan, Frames(plan.markers[0].layout_mm, scale), "mm_per_px", 0.0, {});
  EXPECT_TRUE(std::isnan(scaled.implied_plane_offset_mm));
  EXPECT_EQ(scaled.message.find("plane_offset_mm"), std::string::npos)
      << scaled.message;
}

// Dots stuck by hand 0.3 mm from where layout_mm puts one of them: their
// spacing differs from the layout's by about as much as their shape does,
// so the layout is the one not to trust.
TEST(DistortionCheck, DistrustsALayoutItsDotsDoNotHave) {
  const TestPlan plan = Plan(kLayout);
  std::vector<Eigen::Vector2d> stuck = plan.markers[0].layout_mm;
  stuck[0].y() -= 0.3;
  const DistortionCheck check =
      CheckDistortion(plan, Frames(stuck, 1.0), "tag 0", kCameraHeightMm, {});
  ASSERT_TRUE(check.warn) << check.message;
  std::cout << check.message << "\n";
  EXPECT_GT(check.shape_misfit, 0.5 * std::abs(check.median_ratio - 1.0));
  for (const char* named :
       {"head 'head'", "layout_mm does not describe", "tag 0 scale is kept"}) {
    EXPECT_NE(check.message.find(named), std::string::npos)
        << named << " in " << check.message;
  }
}

// A scale that swings by 0.3 % either way across the field is the lens,
// even where the dots sit 0.015 mm from their layout: a shape misfit of
// 0.06 % is more than the -0.08 % it makes of the average scale, but
// cannot make a 0.5 % spread.
TEST(DistortionCheck, NamesTheLensForAScaleThatDiffersAcrossTheField) {
  const TestPlan plan = Plan(kLayout);
  std::vector<Eigen::Vector2d> stuck = plan.markers[0].layout_mm;
  stuck[0].y() -= 0.015;
  const DistortionCheck check = CheckDistortion(plan, Frames(stuck, 1.0, 0.003),
                                                "tag 0", kCameraHeightMm, {});
  ASSERT_TRUE(check.warn) << check.message;
  EXPECT_GT(check.shape_misfit, 0.5 * std::abs(check.median_ratio - 1.0));
  std::cout << check.message << "\n";
  EXPECT_NE(check.message.find("differs across the field"), std::string::npos)
      << check.message;
  EXPECT_EQ(check.message.find("layout_mm does not describe"),
            std::string::npos)
      << check.message;
}

// A phone's sharpening on a tag of 11 px cells (720p) moved its scale by
// half a percent in rendered footage: the dots, whose shape fits, then
// read 0.6 % large through it. With the tag's scale at risk the check names
// the tag as the likeliest cause, and how large to print it; the same
// disagreement without processing seen is traced to no one cause.
TEST(DistortionCheck, NamesTheTagWhenProcessingPutsItsScaleAtRisk) {
  const TestPlan plan = Plan(kLayout);
  const std::vector<FrameSample> frames =
      Frames(plan.markers[0].layout_mm, 1.006);
  CameraProcessing processing =
      DescribeCameraProcessing({{-0.25, 0.064, 0.0}}, {});
  NoteTagCells({Eigen::Vector2d(100, 100), Eigen::Vector2d(189.6, 100),
                Eigen::Vector2d(189.6, 189.6), Eigen::Vector2d(100, 189.6)},
               {}, std::nullopt, 0.0, &processing);
  ASSERT_TRUE(processing.tag_scale_at_risk);
  const DistortionCheck check =
      CheckDistortion(plan, frames, "tag 0", kCameraHeightMm, processing);
  ASSERT_TRUE(check.warn) << check.message;
  std::cout << check.message << "\n";
  for (const char* named :
       {"most likely the tag's", "cells are 11.2 px", "at least 34 mm across",
        "15 px or more", "tag 0 scale is kept"}) {
    EXPECT_NE(check.message.find(named), std::string::npos)
        << named << " in " << check.message;
  }
  const DistortionCheck plain =
      CheckDistortion(plan, frames, "tag 0", kCameraHeightMm, {});
  EXPECT_NE(plain.message.find("cannot trace to one of"), std::string::npos)
      << plain.message;
  EXPECT_EQ(plain.message.find("most likely"), std::string::npos)
      << plain.message;
}

}  // namespace
}  // namespace softbench
