#include "pipelines/reports/calibration_report.h"

#include <fmt/format.h>

#include <algorithm>

#include "pipelines/reports/html_report.h"
#include "util/statistics.h"

namespace softbench {
namespace {

using json = nlohmann::json;

// Grid over the image for BoardCoverage.
constexpr int kCoverageColumns = 8;
constexpr int kCoverageRows = 6;
// Chart width [px]; its height keeps the image's aspect (equal axes).
constexpr int kCoverageChartWidth = 560;

double MedianError(const CameraCalibration& c) {
  return c.view_errors_px.empty() ? 0.0 : Median(c.view_errors_px);
}

// The board's outline: its four outer inner corners, in order round it.
std::vector<cv::Point2f> Outline(const std::vector<cv::Point2f>& corners,
                                 const BoardOptions& board) {
  const int w = board.corners_x, h = board.corners_y;
  return {corners[0], corners[w - 1], corners[w * h - 1], corners[w * (h - 1)]};
}

json ViewErrorChart(const BoardViews& views, const CameraCalibration& c) {
  json values = json::array();
  for (size_t v = 0; v < c.view_errors_px.size(); ++v) {
    values.push_back(
        {{"view", views.names[v]}, {"error_px", c.view_errors_px[v]}});
  }
  const double limit = kOutlierViewFactor * MedianError(c);
  return {{"$schema", kVegaLiteSchema},
          {"title", "Reprojection error per view (RMS over its corners)"},
          {"width", 560},
          {"layer",
           {{{"data", {{"values", values}}},
             {"mark", "bar"},
             {"encoding",
              {{"x",
                {{"field", "view"},
                 {"type", "nominal"},
                 {"sort", nullptr},
                 {"title", "view"}}},
               {"y",
                {{"field", "error_px"},
                 {"type", "quantitative"},
                 {"title", "reprojection error [px]"}}},
               {"color",
                {{"condition",
                  {{"test", fmt::format("datum.error_px > {}", limit)},
                   {"value", "#d62728"}}},
                 {"value", "#4c78a8"}}},
               {"tooltip",
                {{{"field", "view"}},
                 {{"field", "error_px"}, {"format", ".3f"}}}}}}},
            {{"data", {{"values", {{{"limit_px", limit}}}}}},
             {"mark", {{"type", "rule"}, {"strokeDash", {4, 3}}}},
             {"encoding",
              {{"y", {{"field", "limit_px"}, {"type", "quantitative"}}}}}}}}};
}

json CoverageChart(const BoardViews& views, const BoardOptions& board) {
  json outlines = json::array();
  json corners = json::array();
  for (size_t v = 0; v < views.corners.size(); ++v) {
    const std::vector<cv::Point2f> outline = Outline(views.corners[v], board);
    for (int i = 0; i <= 4; ++i) {
      const cv::Point2f& p = outline[i % 4];
      outlines.push_back({{"view", views.names[v]},
                          {"order", i},
                          {"x_px", p.x},
                          {"y_px", p.y}});
    }
    for (const cv::Point2f& p : views.corners[v]) {
      corners.push_back(
          {{"view", views.names[v]}, {"x_px", p.x}, {"y_px", p.y}});
    }
  }
  const int w = views.size.width, h = views.size.height;
  const json x = {{"field", "x_px"},
                  {"type", "quantitative"},
                  {"scale", {{"domain", {0, w}}, {"nice", false}}},
                  {"title", "image x [px]"}};
  const json y = {
      {"field", "y_px"},
      {"type", "quantitative"},
      {"scale", {{"domain", {0, h}}, {"nice", false}, {"reverse", true}}},
      {"title", "image y [px]"}};
  return {{"$schema", kVegaLiteSchema},
          {"title",
           "Where the boards lay in the image (every view's outline "
           "and corners)"},
          {"width", kCoverageChartWidth},
          {"height", kCoverageChartWidth * h / std::max(w, 1)},
          {"layer",
           {{{"data", {{"values", corners}}},
             {"mark", {{"type", "circle"}, {"size", 6}, {"opacity", 0.5}}},
             {"encoding",
              {{"x", x},
               {"y", y},
               {"color", {{"field", "view"}, {"type", "nominal"}}}}}},
            {{"data", {{"values", outlines}}},
             {"mark", {{"type", "line"}, {"strokeWidth", 1.5}}},
             {"encoding",
              {{"x", x},
               {"y", y},
               {"order", {{"field", "order"}, {"type", "quantitative"}}},
               {"color", {{"field", "view"}, {"type", "nominal"}}},
               {"tooltip", {{{"field", "view"}}}}}}}}}};
}

}  // namespace

std::vector<std::string> OutlierViews(const BoardViews& views,
                                      const CameraCalibration& c) {
  const double median = MedianError(c);
  std::vector<std::string> outliers;
  for (size_t v = 0; v < c.view_errors_px.size() && v < views.names.size();
       ++v) {
    if (c.view_errors_px[v] > kOutlierViewFactor * median) {
      outliers.push_back(views.names[v]);
    }
  }
  return outliers;
}

double BoardCoverage(const BoardViews& views) {
  if (views.size.empty()) return 0.0;
  cv::Mat reached(kCoverageRows, kCoverageColumns, CV_8UC1, cv::Scalar(0));
  const double sx = static_cast<double>(kCoverageColumns) / views.size.width;
  const double sy = static_cast<double>(kCoverageRows) / views.size.height;
  for (const auto& corner : views.corners) {
    for (const cv::Point2f& p : corner) {
      const int col =
          std::clamp(static_cast<int>(p.x * sx), 0, kCoverageColumns - 1);
      const int row =
          std::clamp(static_cast<int>(p.y * sy), 0, kCoverageRows - 1);
      reached.at<uchar>(row, col) = 1;
    }
  }
  return static_cast<double>(cv::countNonZero(reached)) / reached.total();
}

std::string CalibrationReportHtml(const BoardViews& views,
                                  const CameraCalibration& c,
                                  const BoardOptions& board,
                                  const std::string& source) {
  HtmlReport report("Camera calibration: " + source);
  report.AddParagraph(fmt::format(
      "Calibrated from {} of {} views ({} x {} px): reprojection error {:.3f} "
      "px RMS over every corner. Boards reached {:.0f} % of the image (cells "
      "of an {} x {} grid); boards near every edge and corner, tilted toward "
      "the camera, pin the distortion down.",
      c.views, views.looked_at, c.width_px, c.height_px,
      c.reprojection_error_px, 100.0 * BoardCoverage(views), kCoverageColumns,
      kCoverageRows));
  report.AddHeading("Intrinsics");
  const char* names[] = {"fx", "fy", "cx", "cy"};
  const double values[] = {c.camera_matrix(0, 0), c.camera_matrix(1, 1),
                           c.camera_matrix(0, 2), c.camera_matrix(1, 2)};
  std::vector<std::vector<std::string>> rows;
  for (int i = 0; i < 4; ++i) {
    rows.push_back({names[i], fmt::format("{:.2f}", values[i]),
                    fmt::format("{:.2f}", c.intrinsics_std_px[i]), "px"});
  }
  const char* distortion[] = {"k1", "k2", "p1", "p2", "k3"};
  for (int i = 0; i < 5; ++i) {
    rows.push_back({distortion[i], fmt::format("{:.6f}", c.distortion[i]),
                    c.distortion_std[i] > 0.0
                        ? fmt::format("{:.6f}", c.distortion_std[i])
                        : "held at 0",
                    "-"});
  }
  report.AddTable({"parameter", "value", "standard error", "unit"}, rows);
  report.AddHeading("Reprojection error per view");
  report.AddChart(ViewErrorChart(views, c));
  const double median = MedianError(c);
  std::vector<std::vector<std::string>> view_rows;
  for (size_t v = 0; v < c.view_errors_px.size(); ++v) {
    view_rows.push_back(
        {views.names[v], fmt::format("{:.3f}", c.view_errors_px[v]),
         c.view_errors_px[v] > kOutlierViewFactor * median
             ? fmt::format("over {:.0f}x the median: consider dropping it",
                           kOutlierViewFactor)
             : ""});
  }
  for (const std::string& missed : views.missed) {
    view_rows.push_back({missed, "-", "no whole board found"});
  }
  report.AddTable({"view", "reprojection error [px]", "note"}, view_rows);
  report.AddHeading("Coverage of the image");
  report.AddChart(CoverageChart(views, board));
  return report.Render();
}

}  // namespace softbench
