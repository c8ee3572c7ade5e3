// The tune page's script against the C++ it mirrors (issue 31): the HSV
// conversion and the mask that vision/color_segmentation.h computes with
// OpenCV, and cv::connectedComponentsWithStats's blobs, on the same cases,
// run under Node.js (report/check_tune_core.js), so the two cannot drift
// apart.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "pipelines/reports/web_assets.h"
#include "tests/support/scratch_directory.h"
#include "vision/color_segmentation.h"

namespace softbench {
namespace {

// Every grey, every pure and half-saturated hue edge, and random colours.
cv::Mat CasePixels() {
  std::vector<cv::Vec3b> bgr;
  for (int v = 0; v < 256; ++v) bgr.emplace_back(v, v, v);
  for (int a = 0; a < 256; a += 5) {
    for (int b = 0; b < 256; b += 51) {
      for (const auto& [x, y, z] : {std::tuple{a, b, 255},
                                    {255, a, b},
                                    {b, 255, a},
                                    {a, 255, 255},
                                    {255, a, 255},
                                    {255, 255, a}}) {
        bgr.emplace_back(x, y, z);
      }
    }
  }
  std::mt19937 random(31);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int k = 0; k < 20000; ++k) {
    bgr.emplace_back(byte(random), byte(random), byte(random));
  }
  return cv::Mat(bgr, true).reshape(3, 1);
}

nlohmann::json Blobs(const cv::Mat& mask) {
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids,
                                                 8, CV_32S);
  nlohmann::json found = nlohmann::json::array();
  for (int i = 1; i < n; ++i) {
    found.push_back({{"area", stats.at<int>(i, cv::CC_STAT_AREA)},
                     {"x", centroids.at<double>(i, 0)},
                     {"y", centroids.at<double>(i, 1)}});
  }
  return found;
}

TEST(TunePageScript, AgreesWithTheCppOnHsvMasksAndBlobs) {
  ASSERT_NE(kTuneCoreScript.find("function toHsv"), std::string_view::npos);
  const cv::Mat bgr = CasePixels();
  cv::Mat hsv, rgba;
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  cv::cvtColor(bgr, rgba, cv::COLOR_BGR2RGBA);
  nlohmann::json cases;
  cases["rgba"] = std::vector<uint8_t>(rgba.data, rgba.data + rgba.total() * 4);
  cases["hsv"] = std::vector<uint8_t>(hsv.data, hsv.data + hsv.total() * 3);
  // The plan's ranges, one wrapping through hue 0 (red's).
  for (const std::array<int, 6>& bounds :
       {std::array<int, 6>{170, 10, 100, 255, 50, 255},
        std::array<int, 6>{35, 85, 80, 255, 40, 255},
        std::array<int, 6>{0, 179, 0, 30, 200, 255}}) {
    const cv::Mat mask = ColorMask(bgr, HsvRange::FromBounds(bounds));
    std::vector<int> values(mask.total());
    for (size_t i = 0; i < mask.total(); ++i) values[i] = mask.data[i] ? 1 : 0;
    cases["ranges"].push_back({{"bounds", bounds}, {"mask", values}});
  }
  // Shapes that test 8-connectivity: discs, a diagonal chain, a ring with
  // a dot inside, random speckle.
  cv::Mat shapes = cv::Mat::zeros(90, 120, CV_8U);
  cv::circle(shapes, {20, 20}, 9, 255, cv::FILLED);
  cv::circle(shapes, {60, 25}, 14, 255, 3);
  cv::circle(shapes, {60, 25}, 3, 255, cv::FILLED);
  for (int k = 0; k < 15; ++k) shapes.at<uint8_t>(50 + k, 10 + k) = 255;
  std::mt19937 random(7);
  for (int k = 0; k < 400; ++k) {
    shapes.at<uint8_t>(45 + random() % 45, 40 + random() % 80) = 255;
  }
  std::vector<int> shape_mask(shapes.total());
  for (size_t i = 0; i < shapes.total(); ++i)
    shape_mask[i] = shapes.data[i] > 0;
  cases["blobs"].push_back({{"width", shapes.cols},
                            {"height", shapes.rows},
                            {"mask", shape_mask},
                            {"expected", Blobs(shapes)}});

  const std::string path = TestScratch().Write("cases.json", cases.dump());
  const std::string command = std::string(SOFTBENCH_NODE) + " " +
                              SOFTBENCH_SOURCE_DIR +
                              "/report/check_tune_core.js " + path + " > " +
                              TestScratch().Path("said.txt") + " 2>&1";
  const int status = std::system(command.c_str());
  EXPECT_EQ(status, 0) << ReadText(TestScratch().Path("said.txt"));
}

}  // namespace
}  // namespace softbench
