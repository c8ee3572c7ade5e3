// The validation report's data (issue 31): results.csv, summary.json and
// trajectory.csv read back as rows, and its charts' specifications checked
// as data, on a measurement made up frame by frame (no video).
#include "pipelines/reports/validation_report.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "pipelines/reports/validation_charts.h"
#include "pipelines/reports/validation_files.h"
#include "pipelines/validation/lift_correction.h"
#include "tests/support/held_measurement.h"
#include "tests/support/report_page.h"
#include "tests/support/scratch_directory.h"
#include "util/atomic_file.h"
#include "util/csv.h"

namespace softbench {
namespace {

using nlohmann::json;

// Three delta tests (the third repeats the first) and one the bench
// skipped, each head held at the model's equilibrium, scored.
class ValidationReportData : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scratch_ = std::make_unique<ScratchDirectory>();
    const TestPlan plan =
        HeldDeltaPlan("  - {id: t4, pressures: [6, 0, 6], skipped: true}\n");
    // The head rises 0.3 mm toward the camera while actuated, its parallax
    // recorded but not in its positions.
    VideoMeasurement m = HeldMeasurement(plan, 20.0, 0.0);
    LiftHeldHead(plan, 0.3, 0.0, 0.01, &m);
    // Its parallax left in (--no-lift-correction), to be counted in u.
    auto [r, lift] = ScoreTestsCorrectingLift(
        plan, ValidationOptions(), {.mode = LiftCorrectionMode::kNone}, &m);
    validation_ = std::make_unique<VideoValidation>(
        VideoValidation{plan,
                        std::move(m),
                        std::move(r),
                        {{"video", "bench/held.mp4", std::string(64, 'a')}},
                        lift});
  }
  static void TearDownTestSuite() {
    validation_.reset();
    scratch_.reset();
  }
  // `csv` read back: its header and rows, each as name -> cell.
  static std::vector<std::map<std::string, std::string>> Rows(
      const std::string& name, const std::string& csv,
      std::vector<std::string>* header) {
    CsvReader reader(scratch_->Write(name, csv));
    *header = reader.header();
    std::vector<std::map<std::string, std::string>> rows;
    std::vector<std::string_view> fields;
    while (reader.ReadRow(&fields)) {
      EXPECT_EQ(fields.size(), header->size())
          << name << " row " << rows.size();
      auto& row = rows.emplace_back();
      for (size_t i = 0; i < fields.size() && i < header->size(); ++i) {
        row[(*header)[i]] = std::string(fields[i]);
      }
    }
    return rows;
  }
  static const VideoValidation& v() { return *validation_; }
  static std::unique_ptr<ScratchDirectory> scratch_;
  static std::unique_ptr<VideoValidation> validation_;
};

std::unique_ptr<ScratchDirectory> ValidationReportData::scratch_;
std::unique_ptr<VideoValidation> ValidationReportData::validation_;

TEST_F(ValidationReportData, ScoresTheMadeUpHoldsAsThePredictions) {
  ASSERT_EQ(v().result.tests.size(), 3u);
  for (const TestScore& t : v().result.tests) {
    EXPECT_EQ(t.status, "ok") << t.id << ": " << t.reason;
    EXPECT_LT(t.heads[0].model_error_mm, 1e-9) << t.id;
  }
}

TEST_F(ValidationReportData, ResultsCsvHasARowPerTestAndHeadWithUnits) {
  std::vector<std::string> header;
  const auto rows = Rows("results.csv", ResultsCsv(v()), &header);
  ASSERT_EQ(rows.size(), 4u);  // three measured, one skipped; one head
  for (const char* column :
       {"p1_psi", "p3_psi", "measured_dy_mm", "model_error_mm", "u_dy_mm",
        "u_dz_mm", "u_mm", "u_largest_term", "hysteresis_verdict",
        "pressure_unit", "video_sha256"}) {
    EXPECT_NE(std::find(header.begin(), header.end(), column), header.end())
        << column;
  }
  for (int k = 0; k < 3; ++k) {
    const TestScore& t = v().result.tests[k];
    EXPECT_EQ(rows[k].at("test_id"), t.id);
    EXPECT_EQ(rows[k].at("measured_dy_mm"),
              FormatMm(t.heads[0].measured_mm.x()));
    EXPECT_EQ(rows[k].at("model_dz_mm"), FormatMm(t.heads[0].model_mm.y()));
    EXPECT_EQ(rows[k].at("status"), "ok");
    EXPECT_EQ(rows[k].at("pressure_unit"), "psi");
    EXPECT_EQ(rows[k].at("video_file"), "held.mp4");  // the name, not the path
  }
  EXPECT_EQ(rows[3].at("test_id"), "t4");
  EXPECT_EQ(rows[3].at("p1_psi"), "6");
  EXPECT_EQ(rows[3].at("status"), "skipped");
  EXPECT_EQ(rows[3].at("measured_dy_mm"), "");
  EXPECT_EQ(rows[3].at("video_sha256"), std::string(64, 'a'));
}

TEST_F(ValidationReportData, TrajectoryCsvHasARowPerFrameAndHead) {
  std::vector<std::string> header;
  const auto rows =
      Rows("trajectory.csv", TrajectoryCsv(v().plan, v().measurement), &header);
  ASSERT_EQ(rows.size(), v().measurement.frames.size());
  const FrameSample& held = v().measurement.frames[100];  // t1's hold
  EXPECT_EQ(rows[100].at("frame"), "100");
  EXPECT_NEAR(std::stod(rows[100].at("y_mm")),
              held.heads[0].displacement_mm.x(), 1e-5);
  EXPECT_NEAR(std::stod(rows[100].at("z_mm")),
              held.heads[0].displacement_mm.y(), 1e-5);
}

TEST_F(ValidationReportData, SummaryJsonHasEveryTestsWindowsAndTheRepeat) {
  const json summary = SummaryJson(v());
  EXPECT_EQ(summary["pressure_unit"], "psi");
  ASSERT_EQ(summary["tests"].size(), 3u);
  for (const json& test : summary["tests"]) {
    for (const char* window : kWindowNames) {
      EXPECT_GT(test["windows"][window]["frames"].get<int>(), 0)
          << test["id"] << " " << window;
    }
  }
  EXPECT_EQ(summary["skipped_tests"], json::array({"t4"}));
  ASSERT_EQ(summary["repeats"].size(), 1u);
  EXPECT_EQ(summary["repeats"][0]["tests"], json::array({"t1", "t3"}));
  EXPECT_EQ(summary["heads"][0]["model_error"]["tests"], 3);
  EXPECT_EQ(summary["inputs"][0]["file"], "held.mp4");
  EXPECT_EQ(summary["lift_corrected"], false);
  EXPECT_EQ(summary["lift_correction"]["mode"], "none");
  EXPECT_EQ(summary["lift_correction"]["lifts"], 3);
  EXPECT_NE(summary["lift_correction"]["reason"].get<std::string>().find(
                "left in (--no-lift-correction)"),
            std::string::npos);
}

std::vector<json> Charts(const VideoValidation& v) {
  return {PositionChart(v.plan, v.result), ErrorChart(v.plan, v.result),
          LiftChart(v.plan, v.result),
          TrajectoryChart(v.plan, v.measurement, v.result),
          CameraMotionChart(v.measurement, v.result)};
}

TEST_F(ValidationReportData, EveryChartHasATitleASchemaAndData) {
  for (const json& chart : Charts(v())) {
    ASSERT_TRUE(chart.contains("title")) << chart.dump().substr(0, 200);
    EXPECT_EQ(chart["$schema"],
              "https://vega.github.io/schema/vega-lite/v6.json");
    const json& data = chart.contains("data")
                           ? chart["data"]["values"]
                           : chart["layer"][1]["data"]["values"];
    EXPECT_FALSE(data.empty()) << chart["title"];
  }
}

// The page embeds each chart it draws, found by its title.
TEST_F(ValidationReportData, ThePageEmbedsTheChartsFoundByTitle) {
  const std::string html = ValidationReportHtml(v());
  for (const json& chart : Charts(v())) {
    if (ChartTitle(chart).starts_with("Camera shift")) continue;  // still
    EXPECT_EQ(ChartTitled(html, ChartTitle(chart)), chart) << chart["title"];
  }
  EXPECT_TRUE(ChartTitled(html, "Camera shift").is_null())
      << "drawn for a camera taken to be still";
}

// Equal axes (figs. 4.8, 4.16 drawn square): the y and z domains span the
// same millimetres and hold every point.
TEST_F(ValidationReportData, PositionChartHasEqualAxesAroundEveryPoint) {
  const json chart = PositionChart(v().plan, v().result);
  const json& encoding = chart["spec"]["layer"][1]["encoding"];
  const json& y = encoding["x"]["scale"]["domain"];
  const json& z = encoding["y"]["scale"]["domain"];
  EXPECT_NEAR(y[1].get<double>() - y[0].get<double>(),
              z[1].get<double>() - z[0].get<double>(), 1e-12);
  std::set<std::string> series;
  for (const json& p : chart["data"]["values"]) {
    series.insert(p["series"].get<std::string>());
    EXPECT_GE(p["y"].get<double>(), y[0].get<double>());
    EXPECT_LE(p["y"].get<double>(), y[1].get<double>());
    EXPECT_GE(p["z"].get<double>(), z[0].get<double>());
    EXPECT_LE(p["z"].get<double>(), z[1].get<double>());
  }
  EXPECT_EQ(series, (std::set<std::string>{"measured", v().result.model_name,
                                           v().result.baseline_name,
                                           "error line", "U = 2u ellipse"}));
}

// The lift of every measured test, its U, the parallax's shift; and the
// warning that names the heads whose lift moves their displacement.
TEST_F(ValidationReportData, LiftChartHasEveryMeasuredTestsLift) {
  const json chart = LiftChart(v().plan, v().result);
  std::set<std::string> tests;
  for (const json& point : chart["data"]["values"]) {
    tests.insert(point["test"].get<std::string>());
    EXPECT_NEAR(point["lift_mm"].get<double>(), 0.3, 1e-12);
    EXPECT_LE(point["low_mm"].get<double>(), 0.3);
    EXPECT_GE(point["high_mm"].get<double>(), 0.3);
    EXPECT_NEAR(point["shift_mm"].get<double>(), 0.003, 1e-12);
  }
  EXPECT_EQ(tests, (std::set<std::string>{"t1", "t2", "t3"}));
  int warned = 0;
  for (const std::string& w : v().result.warnings) {
    warned +=
        w.find("moved +0.300 mm") != std::string::npos &&
        w.find("left in, and counted in its uncertainty") != std::string::npos;
  }
  EXPECT_EQ(warned, 3);
  // And counted: the parallax left in each displacement is a term of its u.
  for (const TestScore& t : v().result.tests) {
    const std::vector<UncertaintyTerm>& terms = t.heads[0].budget.terms;
    const auto parallax = std::find_if(
        terms.begin(), terms.end(),
        [](const UncertaintyTerm& u) { return u.name == "parallax"; });
    ASSERT_NE(parallax, terms.end()) << t.id;
    EXPECT_NEAR(parallax->u_mm.x(), 0.003, 1e-12) << t.id;
  }
}

TEST_F(ValidationReportData, ErrorChartHasBothModelsForEveryScoredTest) {
  const json chart = ErrorChart(v().plan, v().result);
  // Two bars (model and baseline) and the measurement's U per test.
  std::map<std::string, int> bars_per_test;
  for (const json& bar : chart["data"]["values"]) {
    ++bars_per_test[bar["test"].get<std::string>()];
    EXPECT_GE(bar["error"].get<double>(), 0.0);
    if (bar["model"] == "U = 2u of the measurement") {
      const auto t =
          std::find_if(v().result.tests.begin(), v().result.tests.end(),
                       [&](const TestScore& s) { return s.id == bar["test"]; });
      ASSERT_NE(t, v().result.tests.end());
      EXPECT_EQ(bar["error"].get<double>(), 2.0 * t->heads[0].budget.TotalMm());
    }
  }
  EXPECT_EQ(bars_per_test,
            (std::map<std::string, int>{{"t1", 3}, {"t2", 3}, {"t3", 3}}));
}

// Windows-only runs read some frames: the trajectory's lines break at the
// gaps instead of joining across them.
TEST_F(ValidationReportData,
       TrajectoryChartBreaksItsLinesWhereFramesAreMissing) {
  VideoMeasurement m = v().measurement;
  m.frames.erase(m.frames.begin() + 200, m.frames.begin() + 300);
  const json chart = TrajectoryChart(v().plan, m, v().result);
  std::set<int> segments;
  for (const json& p : chart["layer"][1]["data"]["values"]) {
    segments.insert(p["segment"].get<int>());
  }
  EXPECT_EQ(segments, (std::set<int>{0, 1}));
  EXPECT_EQ(chart["layer"][0]["data"]["values"].size(), 3u * 3u);  // windows
}

// A head with no scored test has no statistics: the index leaves its
// cells empty and the page prints no "nan".
TEST_F(ValidationReportData, IndexLeavesAHeadWithoutScoredTestsEmpty) {
  VideoValidation unscored = v();
  unscored.plan.tests = {unscored.plan.tests[0]};
  unscored.plan.tests[0].pressures = Eigen::Vector3d(1e300, 0, 0);
  unscored.result =
      ScoreTests(unscored.plan, unscored.measurement, ValidationOptions());
  ASSERT_EQ(unscored.result.tests[0].status, "no prediction");
  ASSERT_EQ(unscored.result.model_errors[0].tests, 0);
  const std::string folder = scratch_->Path("index");
  {
    AtomicDirectory report(folder);
    WriteValidationIndex({v(), unscored}, {"scored", "unscored, all"}, report);
    report.Commit();
  }
  std::vector<std::string> header;
  const auto rows = Rows("index.csv", ReadText(folder + "/index.csv"), &header);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].at("tests_measured"), "3");
  EXPECT_NE(rows[0].at("model_mean_mm"), "");
  EXPECT_EQ(rows[1].at("report"), "unscored, all/report.html");
  EXPECT_EQ(rows[1].at("tests_measured"), "0");
  for (const char* column : {"model_mean_mm", "model_max_mm",
                             "baseline_mean_mm", "improvement_percent"}) {
    EXPECT_EQ(rows[1].at(column), "") << column;
  }
  for (const std::string& page :
       {ReadText(folder + "/index.html"), ValidationReportHtml(unscored)}) {
    EXPECT_EQ(page.find(">nan"), std::string::npos);
  }
}

TEST_F(ValidationReportData, SaysThereIsNoUncertaintyWhenNothingIsScored) {
  EXPECT_NE(ValidationReportHtml(v()).find("The largest U is 0.0"),
            std::string::npos);
  VideoValidation unscored = v();
  unscored.plan.tests = {unscored.plan.tests[0]};
  unscored.plan.tests[0].pressures = Eigen::Vector3d(1e300, 0, 0);
  unscored.result =
      ScoreTests(unscored.plan, unscored.measurement, ValidationOptions());
  ASSERT_EQ(unscored.result.model_errors[0].tests, 0);
  const std::string html = ValidationReportHtml(unscored);
  EXPECT_EQ(html.find("The largest U is"), std::string::npos);
  EXPECT_NE(html.find("No test is scored, so there is no U to give."),
            std::string::npos);
}

TEST(EqualDomains, FallsBackToAUnitSquareWithoutPoints) {
  const auto [y, z] = EqualDomains(json::array());
  EXPECT_EQ(y, json::array({-1, 1}));
  EXPECT_EQ(z, json::array({-1, 1}));
}

}  // namespace
}  // namespace softbench
