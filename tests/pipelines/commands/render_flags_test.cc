#include "pipelines/commands/render_flags.h"

#include <gtest/gtest.h>

#include "util/input_error.h"

namespace softbench {
namespace {

TEST(RenderFlags, ParsesCameraBumps) {
  const CameraBump bump = ParseCameraBump("2.5:2,0.5,0.05");
  EXPECT_EQ(bump.time_s, 2.5);
  EXPECT_EQ(bump.shift_px, Eigen::Vector2d(2.0, 0.5));
  EXPECT_EQ(bump.roll_deg, 0.05);
  EXPECT_EQ(ParseCameraBump("4:1,-1").roll_deg, 0.0);
  for (const char* bad : {"4", "4:1", "x:1,2", "4:1,2,3,4"}) {
    EXPECT_THROW(ParseCameraBump(bad), InputError) << bad;
  }
}

TEST(RenderFlags, ParsesResolutions) {
  EXPECT_EQ(ParseResolution("4k"), cv::Size(3840, 2160));
  EXPECT_EQ(ParseResolution("1080x1920"), cv::Size(1080, 1920));
  for (const char* bad : {"", "1080", "1081x720", "8x8", "hd"}) {
    EXPECT_THROW(ParseResolution(bad), InputError) << bad;
  }
}

}  // namespace
}  // namespace softbench
