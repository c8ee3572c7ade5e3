#include "pipelines/synthetic/bayer_sensor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>

namespace softbench {
namespace {

BayerSensorOptions Sensor(Demosaic demosaic, double full_well_e = 0.0,
                          double read_noise_e = 0.0) {
  BayerSensorOptions options;
  options.demosaic = demosaic;
  options.full_well_e = full_well_e;
  options.read_noise_e = read_noise_e;
  return options;
}

// A flat colour is what every demosaic restores exactly: each channel comes
// back as it went in, so the mosaic's layout and OpenCV's pattern name agree
// (a wrong name swaps red and blue).
TEST(BayerSensor, RestoresAFlatColour) {
  const cv::Vec3f bgr(0.7f, 0.45f, 0.2f);
  const cv::Mat light(40, 60, CV_32FC3, cv::Scalar(bgr[0], bgr[1], bgr[2]));
  for (const Demosaic d : {Demosaic::kBilinear, Demosaic::kEdgeAware}) {
    const cv::Mat out = ThroughBayerSensor(light, Sensor(d), 1);
    ASSERT_EQ(out.type(), CV_32FC3);
    ASSERT_EQ(out.size(), light.size());
    for (int v = 2; v < out.rows - 2; ++v) {
      for (int u = 2; u < out.cols - 2; ++u) {
        for (int c = 0; c < 3; ++c) {
          ASSERT_NEAR(out.at<cv::Vec3f>(v, u)[c], bgr[c], 2e-5)
              << "demosaic " << static_cast<int>(d) << " at " << u << "," << v;
        }
      }
    }
  }
}

// Each pixel sees one channel, RGGB from the top-left: red light on a blue
// site is never recorded, on a red site it is.
TEST(BayerSensor, RecordsRedOnlyOnRedSites) {
  for (const auto& [row, col, seen] :
       {std::tuple{10, 10, true}, std::tuple{11, 11, false},
        std::tuple{10, 11, false}, std::tuple{11, 10, false}}) {
    cv::Mat light(24, 24, CV_32FC3, cv::Scalar(0, 0, 0));
    light.at<cv::Vec3f>(row, col)[2] = 1.0f;
    const cv::Mat out =
        ThroughBayerSensor(light, Sensor(Demosaic::kBilinear), 1);
    double red = 0.0;
    for (int v = 0; v < out.rows; ++v) {
      for (int u = 0; u < out.cols; ++u) red += out.at<cv::Vec3f>(v, u)[2];
    }
    EXPECT_EQ(red > 0.5, seen) << row << "," << col << ": " << red;
  }
}

// The raw noise is the electrons' shot noise and the read noise: at a green
// site (kept by the bilinear demosaic) its variance is (n + r^2) / well^2
// for n electrons.
TEST(BayerSensor, NoiseIsShotAndReadNoise) {
  const double well = 4000.0, read = 3.0, level = 0.25;
  const cv::Mat light(256, 256, CV_32FC3, cv::Scalar::all(level));
  const cv::Mat out =
      ThroughBayerSensor(light, Sensor(Demosaic::kBilinear, well, read), 7);
  double sum = 0.0, squares = 0.0;
  int n = 0;
  for (int v = 2; v < out.rows - 2; ++v) {
    for (int u = 2; u < out.cols - 2; ++u) {
      if ((u + v) % 2 == 0) continue;  // green sites: (even, odd), (odd, even)
      const double x = out.at<cv::Vec3f>(v, u)[1];
      sum += x;
      squares += x * x;
      ++n;
    }
  }
  const double mean = sum / n, variance = squares / n - mean * mean;
  const double expected = (level * well + read * read) / (well * well);
  EXPECT_NEAR(mean, level, 5e-4);
  EXPECT_NEAR(variance, expected, 0.05 * expected);
  // The same seed, the same frame; another seed, another.
  EXPECT_EQ(cv::norm(out,
                     ThroughBayerSensor(
                         light, Sensor(Demosaic::kBilinear, well, read), 7),
                     cv::NORM_INF),
            0.0);
  EXPECT_GT(cv::norm(out,
                     ThroughBayerSensor(
                         light, Sensor(Demosaic::kBilinear, well, read), 8),
                     cv::NORM_INF),
            0.0);
}

TEST(BayerSensorOptions, SaysWhatIsWrong) {
  EXPECT_FALSE(Sensor(Demosaic::kNone).Problem());
  EXPECT_FALSE(Sensor(Demosaic::kEdgeAware, 6000, 2).Problem());
  EXPECT_EQ(Sensor(Demosaic::kNone, 6000).Problem(),
            "the sensor's noise needs a colour filter (--bayer)");
  EXPECT_EQ(Sensor(Demosaic::kBilinear, 50).Problem(),
            "the sensor's full well must be 0 (no shot noise) or 100..1e6 "
            "electrons");
  EXPECT_EQ(Sensor(Demosaic::kBilinear, 6000, -1).Problem(),
            "the sensor's read noise must be 0..100 electrons");
  EXPECT_EQ(Sensor(Demosaic::kBilinear, 0, 2).Problem(),
            "the sensor's read noise needs its full well (electrons at white)");
  EXPECT_EQ(ParseDemosaic("edge-aware"), Demosaic::kEdgeAware);
  EXPECT_EQ(ParseDemosaic("bilinear"), Demosaic::kBilinear);
  EXPECT_FALSE(ParseDemosaic("vng"));
}

}  // namespace
}  // namespace softbench
