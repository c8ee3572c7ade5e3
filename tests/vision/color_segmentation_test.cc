#include "vision/color_segmentation.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <random>

#include "vision/color_tuning.h"

namespace softbench {
namespace {

// The built-in red (formats/dot_colors.cc), which wraps through hue 0.
const HsvRange kRed{170, 10, 100, 255, 50, 255};

// A BGR pixel of the given OpenCV HSV.
cv::Vec3b Bgr(int h, int s, int v) {
  cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar(h, s, v)), bgr;
  cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
  return bgr.at<cv::Vec3b>(0, 0);
}

TEST(HsvRange, RedWrapsThroughOneEighty) {
  const HsvRange red = kRed;
  EXPECT_TRUE(red.Wraps());
  EXPECT_TRUE(red.Contains({178, 200, 200}));
  EXPECT_TRUE(red.Contains({3, 200, 200}));
  EXPECT_FALSE(red.Contains({90, 200, 200}));
  EXPECT_FALSE(red.Contains({3, 40, 200}));  // unsaturated: the resin
  // The mask agrees with Contains on both sides of the wrap.
  cv::Mat image(1, 4, CV_8UC3);
  image.at<cv::Vec3b>(0, 0) = Bgr(178, 200, 200);
  image.at<cv::Vec3b>(0, 1) = Bgr(2, 200, 200);
  image.at<cv::Vec3b>(0, 2) = Bgr(60, 200, 200);
  image.at<cv::Vec3b>(0, 3) = Bgr(160, 200, 200);
  const cv::Mat mask = ColorMask(image, red);
  EXPECT_EQ(mask.at<uint8_t>(0, 0), 255);
  EXPECT_EQ(mask.at<uint8_t>(0, 1), 255);
  EXPECT_EQ(mask.at<uint8_t>(0, 2), 0);
  EXPECT_EQ(mask.at<uint8_t>(0, 3), 0);
}

TEST(ColorMask, MatchesOpenCvsInRangeOnRandomPixels) {
  // Every pixel's verdict as cv::inRange gives it (two ranges and their
  // union for a hue that wraps), for ranges that wrap and ranges that do
  // not.
  std::mt19937 random(11);
  cv::Mat bgr(64, 96, CV_8UC3), hsv;
  cv::randu(bgr, cv::Scalar::all(0), cv::Scalar::all(256));
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  for (int trial = 0; trial < 200; ++trial) {
    HsvRange r;
    r.hue_low = static_cast<int>(random() % 180);
    r.hue_high = static_cast<int>(random() % 180);
    r.saturation_low = static_cast<int>(random() % 200);
    r.saturation_high = r.saturation_low + static_cast<int>(random() % 56);
    r.value_low = static_cast<int>(random() % 200);
    r.value_high = r.value_low + static_cast<int>(random() % 56);
    cv::Mat expected;
    const cv::Scalar high(r.Wraps() ? 179 : r.hue_high, r.saturation_high,
                          r.value_high);
    cv::inRange(hsv, cv::Scalar(r.hue_low, r.saturation_low, r.value_low), high,
                expected);
    if (r.Wraps()) {
      cv::Mat lower;
      cv::inRange(hsv, cv::Scalar(0, r.saturation_low, r.value_low),
                  cv::Scalar(r.hue_high, r.saturation_high, r.value_high),
                  lower);
      expected |= lower;
    }
    ASSERT_EQ(cv::countNonZero(ColorMask(bgr, r) != expected), 0)
        << "hue " << r.hue_low << ".." << r.hue_high;
  }
}

TEST(FindBlobs, KeepsDotsAndRejectsATubeAndSpecks) {
  cv::Mat image(200, 300, CV_8UC3, cv::Scalar(214, 217, 220));
  const cv::Scalar red(40, 40, 200);
  cv::circle(image, {50, 50}, 10, red, cv::FILLED, cv::LINE_AA);
  cv::circle(image, {120, 60}, 10, red, cv::FILLED, cv::LINE_AA);
  cv::line(image, {20, 150}, {280, 170}, red, 9);               // a tube
  cv::circle(image, {250, 40}, 1, red, cv::FILLED);             // a speck
  cv::rectangle(image, {180, 80}, {240, 88}, red, cv::FILLED);  // a bar
  SegmentationOptions options;
  options.dot_radius_px = 10.0;
  const BlobSummary blobs = SegmentDots(image, kRed, options, {5, 7});
  ASSERT_EQ(blobs.accepted.size(), 2u);
  EXPECT_NEAR(blobs.accepted[0].centroid.x(), 55.0, 0.2);  // offset applied
  EXPECT_NEAR(blobs.accepted[0].centroid.y(), 57.0, 0.2);
  EXPECT_GT(blobs.accepted[0].circularity, 0.8);
  EXPECT_EQ(blobs.TotalRejected(), 2);  // tube (area) and bar (shape)
}

TEST(LearnHsvRange, HoldsTheDotsAndWrapsForRed) {
  cv::Mat image(100, 100, CV_8UC3, cv::Scalar(214, 217, 220));
  cv::Mat cores = cv::Mat::zeros(100, 100, CV_8UC1);
  cv::RNG rng(3);
  for (int y = 20; y < 40; ++y) {
    for (int x = 20; x < 40; ++x) {
      // Reds on both sides of hue 0.
      const int h = (180 + rng.uniform(-6, 7)) % 180;
      image.at<cv::Vec3b>(y, x) = Bgr(h, rng.uniform(170, 230), 190);
      cores.at<uint8_t>(y, x) = 255;
    }
  }
  const LearnedHsvRange learned = LearnHsvRange(image, cores, cores);
  EXPECT_EQ(learned.dot_pixels, 400);
  EXPECT_DOUBLE_EQ(learned.dot_coverage, 1.0);
  EXPECT_EQ(learned.outside_pixels, 0);
  EXPECT_TRUE(learned.range.Wraps());
  EXPECT_GE(learned.range.hue_low, 160);
  EXPECT_LE(learned.range.hue_high, 20);
  // A valid range (formats/dot_colors.h's CheckHsvBounds, which vision/
  // cannot use): hue 0-179, 0 <= low <= high <= 255 for the others.
  for (const int hue : {learned.range.hue_low, learned.range.hue_high}) {
    EXPECT_GE(hue, 0);
    EXPECT_LE(hue, 179);
  }
  EXPECT_GE(learned.range.saturation_low, 0);
  EXPECT_LE(learned.range.saturation_low, learned.range.saturation_high);
  EXPECT_LE(learned.range.saturation_high, 255);
  EXPECT_GE(learned.range.value_low, 0);
  EXPECT_LE(learned.range.value_low, learned.range.value_high);
  EXPECT_LE(learned.range.value_high, 255);
}

// Reddish orange (hue 8) falls inside the built-in red range (170..10): the
// suggestion keeps the red dots only and names the orange ones.
TEST(TuneColor, LeavesOrangeOutOfARedRange) {
  cv::Mat image(240, 320, CV_8UC3, cv::Scalar(150, 155, 160));
  const cv::Scalar red(40, 40, 200), orange(0, 70, 255);
  for (int i = 0; i < 3; ++i) {
    cv::circle(image, {60 + 50 * i, 70}, 10, red, cv::FILLED, cv::LINE_AA);
    cv::circle(image, {60 + 50 * i, 170}, 10, orange, cv::FILLED, cv::LINE_AA);
  }
  const HsvRange built_in = HsvRange::FromBounds({170, 10, 100, 255, 50, 255});
  cv::Mat hsv;
  cv::cvtColor(image, hsv, cv::COLOR_BGR2HSV);
  const cv::Vec3b orange_hsv = hsv.at<cv::Vec3b>(170, 60);
  const cv::Vec3b red_hsv = hsv.at<cv::Vec3b>(70, 60);
  ASSERT_TRUE(built_in.Contains(orange_hsv));  // the problem
  const ColorTuning tuning = TuneColor(image, built_in, {});
  ASSERT_TRUE(tuning.found);
  EXPECT_EQ(tuning.blobs.accepted.size(), 3u);
  ASSERT_EQ(tuning.other_hue.size(), 3u);
  for (const Blob& blob : tuning.blobs.accepted) {
    EXPECT_NEAR(blob.centroid.y(), 70.0, 1.0);
  }
  EXPECT_NEAR(tuning.other_hues[0], orange_hsv[0], 1.0);
  EXPECT_TRUE(tuning.learned.range.Contains(red_hsv));
  EXPECT_FALSE(tuning.learned.range.Contains(orange_hsv));
  EXPECT_EQ(tuning.learned.outside_pixels, 0);
}

}  // namespace
}  // namespace softbench
