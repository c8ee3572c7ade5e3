// The camera-calibration report's data (issue 31): which views it names to
// drop, how much of the image the boards covered, and its charts' data,
// found on the page by title, on views made up corner by corner.
#include "pipelines/reports/calibration_report.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tests/support/report_page.h"

namespace softbench {
namespace {

using nlohmann::json;

// A 9 x 6 board's inner corners, `pitch_px` apart, from `origin`.
std::vector<cv::Point2f> Board(cv::Point2f origin, float pitch_px) {
  std::vector<cv::Point2f> corners;
  for (int row = 0; row < 6; ++row) {
    for (int col = 0; col < 9; ++col) {
      corners.push_back(origin + cv::Point2f(col * pitch_px, row * pitch_px));
    }
  }
  return corners;
}

// Three 1080p views with a board each, the third fitted worst.
struct MadeUpCalibration {
  BoardViews views;
  CameraCalibration calibration;
  MadeUpCalibration() {
    views.size = cv::Size(1920, 1080);
    views.corners = {Board({10, 10}, 5), Board({900, 400}, 40),
                     Board({1500, 800}, 20)};
    views.names = {"a.png", "b.png", "c.png"};
    views.missed = {"d.png"};
    views.looked_at = 4;
    calibration.width_px = 1920;
    calibration.height_px = 1080;
    calibration.views = 3;
    calibration.view_errors_px = {0.2, 0.25, 0.9};
  }
  // The report page's chart whose title starts with `title` (null if none).
  json ChartTitled(const std::string& title) const {
    return softbench::ChartTitled(
        CalibrationReportHtml(views, calibration, BoardOptions(), "views/"),
        title);
  }
};

TEST(CalibrationReport, NamesOnlyViewsOverTwiceTheMedianError) {
  const MadeUpCalibration made_up;
  EXPECT_EQ(OutlierViews(made_up.views, made_up.calibration),
            std::vector<std::string>{"c.png"});
}

// Coverage counts the cells of an 8 x 6 grid some board's corner lies in.
TEST(CalibrationReport, CoverageCountsTheGridCellsTheCornersReach) {
  BoardViews views;
  views.size = cv::Size(1920, 1080);  // cells of 240 x 180 px
  views.corners = {Board({10, 10}, 5)};
  EXPECT_DOUBLE_EQ(BoardCoverage(views), 1.0 / 48.0);
  views.corners.push_back(Board({10, 10}, 200));  // columns 0-6, rows 0-5
  EXPECT_DOUBLE_EQ(BoardCoverage(views), 7.0 * 6.0 / 48.0);
  views.corners.push_back({{1919.0f, 1079.0f}});  // the last column's corner
  EXPECT_DOUBLE_EQ(BoardCoverage(views), 43.0 / 48.0);
}

TEST(CalibrationReport, ErrorChartHasABarPerViewAndTheOutlierLimit) {
  const MadeUpCalibration made_up;
  const json chart = made_up.ChartTitled("Reprojection error per view");
  ASSERT_FALSE(chart.is_null());
  const json& bars = chart["layer"][0]["data"]["values"];
  ASSERT_EQ(bars.size(), 3u);  // the missed view has no error
  for (size_t v = 0; v < bars.size(); ++v) {
    EXPECT_EQ(bars[v]["view"], made_up.views.names[v]);
    EXPECT_EQ(bars[v]["error_px"], made_up.calibration.view_errors_px[v]);
  }
  EXPECT_DOUBLE_EQ(
      chart["layer"][1]["data"]["values"][0]["limit_px"].get<double>(),
      kOutlierViewFactor * 0.25);
}

// Equal axes: the chart keeps the image's aspect, and each view's outline
// is closed round its four outer corners.
TEST(CalibrationReport, CoverageChartKeepsTheImagesAspectAndClosesOutlines) {
  const MadeUpCalibration made_up;
  const json chart = made_up.ChartTitled("Where the boards lay in the image");
  ASSERT_FALSE(chart.is_null());
  EXPECT_EQ(chart["width"].get<int>() * 1080,
            chart["height"].get<int>() * 1920);
  EXPECT_EQ(chart["layer"][0]["data"]["values"].size(), 3u * 54u);
  const json& outline = chart["layer"][1]["data"]["values"];
  ASSERT_EQ(outline.size(), 3u * 5u);
  for (size_t v = 0; v < 3; ++v) {
    const json& first = outline[5 * v];
    const json& last = outline[5 * v + 4];
    EXPECT_EQ(first["x_px"], last["x_px"]);
    EXPECT_EQ(first["y_px"], last["y_px"]);
    EXPECT_EQ(first["view"], made_up.views.names[v]);
  }
  EXPECT_EQ(outline[2]["x_px"].get<double>(), 10.0 + 8 * 5.0);  // far corner
  EXPECT_EQ(outline[2]["y_px"].get<double>(), 10.0 + 5 * 5.0);
}

}  // namespace
}  // namespace softbench
