#include "pipelines/formats/dot_colors.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "vision/color_segmentation.h"

namespace softbench {
namespace {

TEST(DotColors, EveryColourHasAValidRangeThatHoldsItsOwnInk) {
  std::set<std::string_view> names;
  for (const DotColor& color : DotColors()) {
    EXPECT_TRUE(names.insert(color.name).second) << color.name;
    EXPECT_FALSE(CheckHsvBounds(color.hsv_bounds)) << color.name;
    // The renderer's ink is found by the colour's own range, and by no
    // other colour's: each name means one thing end to end.
    cv::Mat ink(
        1, 1, CV_8UC3,
        cv::Scalar(color.ink_bgr[0], color.ink_bgr[1], color.ink_bgr[2]));
    for (const DotColor& other : DotColors()) {
      const cv::Mat mask =
          ColorMask(ink, HsvRange::FromBounds(other.hsv_bounds));
      EXPECT_EQ(mask.at<uint8_t>(0, 0) != 0, &other == &color)
          << color.name << " ink in " << other.name << "'s range";
    }
  }
}

TEST(DotColors, FindsKnownNamesOnly) {
  ASSERT_NE(FindDotColor("magenta"), nullptr);
  EXPECT_EQ(FindDotColor("magenta")->name, "magenta");
  EXPECT_EQ(FindDotColor("purple"), nullptr);
  EXPECT_EQ(FindDotColor(""), nullptr);
  EXPECT_EQ(FindDotColor("Red"), nullptr);
}

TEST(DotColors, HsvBoundsAreChecked) {
  EXPECT_FALSE(CheckHsvBounds({170, 10, 100, 255, 50, 255}));  // wraps
  EXPECT_TRUE(CheckHsvBounds({0, 200, 0, 255, 0, 255}));       // hue > 179
  EXPECT_TRUE(CheckHsvBounds({0, 10, 200, 100, 0, 255}));      // s_low > s_high
  EXPECT_TRUE(CheckHsvBounds({0, 10, 0, 255, -1, 255}));       // v < 0
}

TEST(DotColors, NamesAreListedForPeople) {
  EXPECT_EQ(DotColorNames(), "red, green, blue, yellow or magenta");
}

}  // namespace
}  // namespace softbench
