// Naming the camera's processing from the tag's border (issue 28).
#include "pipelines/measurement/camera_processing.h"

#include <gtest/gtest.h>

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
