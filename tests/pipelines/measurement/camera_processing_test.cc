// Naming the camera's processing from the tag's border (issue 28).
#include "pipelines/measurement/camera_processing.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace softbench {
namespace {

std::vector<std::string> Names(const CameraProcessing& p) {
  std::vector<std::string> names;
  for (const ProcessingEffect& e : p.effects) names.push_back(e.name);
  return names;
}

TEST(CameraProcessing, TakesEachSignsMedianOverTheFrames) {
  // One frame far off each way (a frame in mid-knock) moves no median.
  const std::vector<TagEdgeSigns> frames = {{0.01, 0.002, 0.003},
                                            {0.02, 0.004, 0.001},
                                            {-0.5, 0.5, -0.2},
                                            {0.015, 0.003, 0.002},
                                            {0.9, 0.0, 0.3}};
  const CameraProcessing p = DescribeCameraProcessing(frames, {});
  ASSERT_TRUE(p.measured);
  EXPECT_EQ(p.frames, 5);
  EXPECT_DOUBLE_EQ(p.signs.edge_shift_px, 0.015);
  EXPECT_DOUBLE_EQ(p.signs.halo, 0.003);
  EXPECT_DOUBLE_EQ(p.signs.white_ratio, 0.002);
  EXPECT_TRUE(p.effects.empty());
  EXPECT_NE(p.Summary().find("no effect of processing seen"), std::string::npos)
      << p.Summary();
}

TEST(CameraProcessing, NamesEachSignAboveItsBar) {
  const CameraProcessingOptions options;
  const auto names = [&](const TagEdgeSigns& s) {
    return Names(DescribeCameraProcessing({s}, options));
  };
  const std::string halos = "sharpening halos";
  const std::string curve =
      "a tone curve or filtering the video's transfer does not describe";
  const std::string gain =
      "local tone mapping or light falling off across the tag";
  EXPECT_EQ(names({0.0, 1.01 * options.halo, 0.0}),
            std::vector<std::string>{halos});
  EXPECT_TRUE(names({0.0, 0.99 * options.halo, 0.0}).empty());
  // Halos, and only they, have the dots weighed in codes.
  EXPECT_TRUE(
      DescribeCameraProcessing({{0.0, 1.01 * options.halo, 0.0}}, options)
          .sharpened);
  EXPECT_FALSE(
      DescribeCameraProcessing({{0.2, 0.99 * options.halo, 0.03}}, options)
          .sharpened);
  // Toward either side.
  EXPECT_EQ(names({-1.01 * options.edge_shift_px, 0.0, 0.0}),
            std::vector<std::string>{curve});
  EXPECT_EQ(names({1.01 * options.edge_shift_px, 0.0, 0.0}),
            std::vector<std::string>{curve});
  EXPECT_TRUE(names({0.99 * options.edge_shift_px, 0.0, 0.0}).empty());
  EXPECT_EQ(names({0.0, 0.0, -1.01 * options.white_ratio}),
            std::vector<std::string>{gain});
  EXPECT_EQ(names({0.0, 0.0, 1.01 * options.white_ratio}),
            std::vector<std::string>{gain});
  EXPECT_EQ(names({0.2, 0.08, 0.03}),
            (std::vector<std::string>{halos, curve, gain}));
  // Each says what it saw, with the sign's size and which way.
  const CameraProcessing p = DescribeCameraProcessing({{-0.194, 0.0, 0.0}}, {});
  ASSERT_EQ(p.effects.size(), 1u);
  EXPECT_NE(p.effects[0].seen.find("0.194 px toward its dark side"),
            std::string::npos)
      << p.effects[0].seen;
}

TEST(CameraProcessing, SaysWhyWithoutFrames) {
  const CameraProcessing p = DescribeCameraProcessing({}, {});
  EXPECT_FALSE(p.measured);
  EXPECT_EQ(p.Summary(),
            "not measured: no frame's tag border showed a white data cell");
}

TEST(CameraProcessingOptions, RefusesBarsThatAreNotPositive) {
  EXPECT_FALSE(CameraProcessingOptions{}.Problem());
  CameraProcessingOptions options;
  options.halo = 0.0;
  EXPECT_EQ(options.Problem(), "halo must be > 0");
  options = {};
  options.edge_shift_px = -1.0;
  EXPECT_EQ(options.Problem(), "edge_shift_px must be > 0");
  options = {};
  options.white_ratio = std::nan("");
  EXPECT_EQ(options.Problem(), "white_ratio must be > 0");
  options = {};
  options.min_cell_px = -1.0;
  EXPECT_EQ(options.Problem(), "min_cell_px must be >= 0");
}

// The tag's corners (a square turned 30 degrees, sides of `side_px`).
std::array<Eigen::Vector2d, 4> Square(double side_px) {
  const Eigen::Vector2d u(std::cos(0.5236), std::sin(0.5236));
  const Eigen::Vector2d v(-u.y(), u.x());
  const Eigen::Vector2d at(300.0, 200.0);
  return {at, at + side_px * u, at + side_px * (u + v), at + side_px * v};
}

// Processing on the codes moves a small-celled tag's scale (issue 28: up to
// half a percent at 720p's 11 px cells): the effects on the codes say so,
// the local tone mapping's does not, and large cells or unprocessed codes
// leave the scale trusted.
TEST(CameraProcessing, PutsASmallCelledTagsScaleAtRiskOnlyUnderProcessing) {
  const CameraProcessingOptions options;
  CameraProcessing p = DescribeCameraProcessing({{-0.25, 0.064, 0.03}}, {});
  NoteTagCells(Square(89.6), options, std::nullopt, 0.0, &p);
  EXPECT_NEAR(p.tag_cell_px, 11.2, 1e-9);
  EXPECT_TRUE(p.tag_scale_at_risk);
  ASSERT_EQ(p.effects.size(), 3u);
  for (int e = 0; e < 2; ++e) {
    EXPECT_NE(p.effects[e].handling.find("cells are 11.2 px"),
              std::string::npos)
        << p.effects[e].handling;
  }
  EXPECT_EQ(p.effects[2].handling.find("cells are"), std::string::npos)
      << p.effects[2].handling;
  EXPECT_NE(p.Summary().find("cells of 11.2 px they may move its scale"),
            std::string::npos)
      << p.Summary();
  // An edge shift alone (a tone curve) puts it at risk as halos do.
  p = DescribeCameraProcessing({{-0.25, 0.0, 0.0}}, {});
  NoteTagCells(Square(89.6), options, std::nullopt, 0.0, &p);
  EXPECT_TRUE(p.tag_scale_at_risk);
  // Cells of 15 px or more: the midlines hold.
  p = DescribeCameraProcessing({{-0.25, 0.064, 0.0}}, {});
  NoteTagCells(Square(8 * 15.1), options, std::nullopt, 0.0, &p);
  EXPECT_NEAR(p.tag_cell_px, 15.1, 1e-9);
  EXPECT_FALSE(p.tag_scale_at_risk);
  EXPECT_EQ(p.effects[0].handling.find("cells are"), std::string::npos);
  EXPECT_EQ(p.Summary().find("may move"), std::string::npos) << p.Summary();
  // Small cells, codes unprocessed (local tone mapping only).
  p = DescribeCameraProcessing({{0.0, 0.002, 0.03}}, {});
  NoteTagCells(Square(89.6), options, std::nullopt, 0.0, &p);
  EXPECT_FALSE(p.tag_scale_at_risk);
  EXPECT_NEAR(p.tag_cell_px, 11.2, 1e-9);
}

// Where the tag was fitted whole, its scale is no longer at risk, and the
// effects on the codes say what was fitted and how far it moved the scale;
// a fit not found keeps the risk and says why.
TEST(CameraProcessing, SaysWhatFittingTheTagWholeDid) {
  const CameraProcessingOptions options;
  CameraProcessing p = DescribeCameraProcessing({{-0.25, 0.064, 0.03}}, {});
  TagModelFit fit;
  fit.found = true;
  fit.tone_curve = 0.6;
  NoteTagCells(Square(89.6), options, fit, -0.0051, &p);
  EXPECT_FALSE(p.tag_scale_at_risk);
  ASSERT_TRUE(p.tag_model.has_value());
  EXPECT_DOUBLE_EQ(p.tag_model_scale_change, -0.0051);
  EXPECT_NE(p.effects[0].handling.find("fitted whole"), std::string::npos)
      << p.effects[0].handling;
  EXPECT_NE(p.effects[0].handling.find("tone curve 0.60"), std::string::npos)
      << p.effects[0].handling;
  EXPECT_NE(p.effects[0].handling.find("-0.510 % from the midlines'"),
            std::string::npos)
      << p.effects[0].handling;
  EXPECT_EQ(p.Summary().find("may move"), std::string::npos) << p.Summary();
  fit.found = false;
  fit.why_not = "the fit did not converge";
  p = DescribeCameraProcessing({{-0.25, 0.064, 0.03}}, {});
  NoteTagCells(Square(89.6), options, fit, 0.0, &p);
  EXPECT_TRUE(p.tag_scale_at_risk);
  EXPECT_NE(p.effects[0].handling.find(
                "fitting the tag whole failed: the fit did not converge"),
            std::string::npos)
      << p.effects[0].handling;
}

// A rolling shutter seen in the registration joins the effects, with its
// readout; one measured but not seen, or not measured, does not. The tag
// border's summary names only what the border showed.
TEST(CameraProcessing, NamesARollingShutterOnlyWhenSeen) {
  RollingShutter shutter;
  shutter.measured = true;
  shutter.rows_readout_s = 0.0283;
  shutter.rows_standard_error_s = 0.0011;
  shutter.shear_rms_px = 0.41;
  CameraProcessing p = DescribeCameraProcessing({{0.0, 0.002, 0.0}}, {});
  NameRollingShutter(shutter, &p);
  EXPECT_TRUE(p.effects.empty());
  EXPECT_TRUE(p.rolling_shutter.measured);
  shutter.seen = true;
  NameRollingShutter(shutter, &p);
  ASSERT_EQ(Names(p), std::vector<std::string>{"rolling-shutter shear"});
  EXPECT_NE(p.effects[0].seen.find("28.3 ± 1.1 ms"), std::string::npos)
      << p.effects[0].seen;
  EXPECT_NE(p.effects[0].seen.find("0.410 px RMS"), std::string::npos)
      << p.effects[0].seen;
  EXPECT_NE(p.Summary().find("no effect of processing seen"), std::string::npos)
      << p.Summary();
}

}  // namespace
}  // namespace softbench
