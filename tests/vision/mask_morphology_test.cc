#include "vision/mask_morphology.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <random>

namespace softbench {
namespace {

// What OpenThenClose must match: OpenCV's opening then closing.
cv::Mat OpenCvOpenThenClose(const cv::Mat& mask, int radius) {
  const cv::Mat disk = cv::getStructuringElement(
      cv::MORPH_ELLIPSE, {2 * radius + 1, 2 * radius + 1});
  cv::Mat out;
  cv::morphologyEx(mask, out, cv::MORPH_OPEN, disk);
  cv::morphologyEx(out, out, cv::MORPH_CLOSE, disk);
  return out;
}

int DifferingPixels(const cv::Mat& a, const cv::Mat& b) {
  return cv::countNonZero(a != b);
}

TEST(OpenThenClose, MatchesOpenCvOnRandomMasks) {
  // Sizes from one pixel to several 64-pixel words, densities from specks
  // to holes, radii past a word's worth of shift: every border case.
  std::mt19937 random(7);
  int compared = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const int rows = 1 + static_cast<int>(random() % 90);
    const int cols = 1 + static_cast<int>(random() % 200);
    const int radius = 1 + static_cast<int>(random() % 9);
    const double density = (random() % 101) / 100.0;
    cv::Mat mask(rows, cols, CV_8UC1);
    std::bernoulli_distribution set(density);
    for (int y = 0; y < rows; ++y) {
      for (int x = 0; x < cols; ++x) mask.at<uint8_t>(y, x) = set(random) * 255;
    }
    const cv::Mat expected = OpenCvOpenThenClose(mask, radius);
    OpenThenClose(radius, &mask);
    ASSERT_EQ(DifferingPixels(mask, expected), 0)
        << rows << " x " << cols << ", radius " << radius << ", density "
        << density;
    ++compared;
  }
  EXPECT_EQ(compared, 600);
}

TEST(OpenThenClose, CleansADotAsOpenCvDoesInARegionView) {
  // A dot with a speck beside it and a hole in it, in a view into a larger
  // image (rows not contiguous): the speck goes, the hole fills, and the
  // pixels outside the view are untouched.
  cv::Mat image(120, 160, CV_8UC1, cv::Scalar(0));
  cv::Mat region = image(cv::Rect(30, 20, 70, 60));
  cv::circle(region, {35, 30}, 12, cv::Scalar(255), cv::FILLED);
  region.at<uint8_t>(30, 35) = 0;   // a hole
  region.at<uint8_t>(5, 60) = 255;  // a speck
  image.at<uint8_t>(0, 0) = 255;    // outside the view
  const cv::Mat expected = OpenCvOpenThenClose(region.clone(), 2);
  OpenThenClose(2, &region);
  EXPECT_EQ(DifferingPixels(region, expected), 0);
  EXPECT_EQ(region.at<uint8_t>(30, 35), 255);
  EXPECT_EQ(region.at<uint8_t>(5, 60), 0);
  EXPECT_EQ(image.at<uint8_t>(0, 0), 255);
}

}  // namespace
}  // namespace softbench
