// The fit report's data (issue 31): its files' rows and its charts'
// specifications checked as data, not as HTML text.
#include <gtest/gtest.h>

#include <memory>
#include <nlohmann/json.hpp>
#include <set>

#include "pipelines/characterisation/fit_analysis.h"
#include "pipelines/reports/fit_charts.h"
#include "pipelines/reports/fit_files.h"
#include "pipelines/synthetic/force_logs.h"
#include "tests/support/scratch_directory.h"
#include "util/csv.h"

namespace softbench {
namespace {

// One fit of the thesis's protocol at a low rate, shared by the suite.
class FitReportData : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scratch_ = std::make_unique<ScratchDirectory>();
    ForceLogFilesOptions logs;
    logs.synthetic.sample_rate_hz = 40.0;
    logs.synthetic.seed = 3;
    logs.progress = false;
    WriteForceLogFiles(scratch_->Path("logs"), logs);
    FitAnalysisOptions fit;
    fit.input_path = scratch_->Path("logs/manifest.yaml");
    fit.progress = false;
    run_ = std::make_unique<FitRun>(RunFitAnalysis(fit));
  }
  static void TearDownTestSuite() {
    run_.reset();
    scratch_.reset();
  }
  // `csv` read back: its header and rows.
  static std::vector<std::vector<std::string>> Rows(
      const std::string& name, const std::string& csv,
      std::vector<std::string>* header) {
    CsvReader reader(scratch_->Write(name, csv));
    *header = reader.header();
    std::vector<std::vector<std::string>> rows;
    std::vector<std::string_view> fields;
    while (reader.ReadRow(&fields)) {
      rows.emplace_back(fields.begin(), fields.end());
    }
    return rows;
  }
  static std::unique_ptr<ScratchDirectory> scratch_;
  static std::unique_ptr<FitRun> run_;
};

std::unique_ptr<ScratchDirectory> FitReportData::scratch_;
std::unique_ptr<FitRun> FitReportData::run_;

TEST_F(FitReportData, ModelsCsvHasOneRowPerModelAndUnitsInItsColumns) {
  std::vector<std::string> header;
  const auto rows = Rows("models.csv", FitModelsCsv(*run_), &header);
  ASSERT_EQ(rows.size(), run_->models.size());
  for (size_t m = 0; m < rows.size(); ++m) {
    EXPECT_EQ(rows[m][0], run_->models[m].name);
  }
  for (const char* column : {"A_z_mm2", "A_z_se_mm2", "k_theta_n_per_rad"}) {
    EXPECT_NE(std::find(header.begin(), header.end(), column), header.end())
        << column;
  }
}

TEST_F(FitReportData, PressureBinsCsvHasOneRowPerBinInTheLogsUnit) {
  const std::vector<FitPressureBin> bins = FitPressureBins(*run_);
  ASSERT_FALSE(bins.empty());
  std::vector<std::string> header;
  const auto rows = Rows("bins.csv", FitPressureBinsCsv(*run_, bins), &header);
  EXPECT_EQ(rows.size(), bins.size());
  EXPECT_EQ(header[2], "pressure_" + run_->pressure_unit);
  std::set<std::string> tests;
  for (const auto& row : rows) tests.insert(row[0]);
  EXPECT_EQ(tests.size(), run_->tests.size());
}

TEST_F(FitReportData, EveryChartHasATitleASchemaAndData) {
  const std::vector<FitPressureBin> bins = FitPressureBins(*run_);
  int chosen = 0;
  while (!run_->fits[chosen].ok) ++chosen;
  for (const nlohmann::json& chart :
       {ForcePressureChart(*run_, bins, 0), ForcePressureChart(*run_, bins, 1),
        StaticOffsetChart(*run_, run_->fits[chosen], run_->models[chosen]),
        StaticOffsetProjectionChart(*run_, run_->fits[chosen],
                                    run_->models[chosen]),
        EffectiveAreaChart(*run_, run_->fits[chosen]),
        ResidualChart(*run_, bins), TestRmseChart(*run_)}) {
    ASSERT_TRUE(chart.contains("title")) << chart.dump().substr(0, 200);
    EXPECT_EQ(chart["$schema"],
              "https://vega.github.io/schema/vega-lite/v6.json");
    EXPECT_FALSE(chart["data"]["values"].empty()) << chart["title"];
  }
}

// Every fitted model draws a line on every configuration's panel, beside
// the measured up and down ramps.
TEST_F(FitReportData, ForceAgainstPressureDrawsEveryFittedModel) {
  const nlohmann::json chart =
      ForcePressureChart(*run_, FitPressureBins(*run_), 0);
  std::set<std::string> series;
  for (const nlohmann::json& value : chart["data"]["values"]) {
    series.insert(value["series"].get<std::string>());
  }
  EXPECT_TRUE(series.count("measured, up") && series.count("measured, down"));
  for (size_t m = 0; m < run_->models.size(); ++m) {
    EXPECT_EQ(series.count(run_->models[m].name), run_->fits[m].ok ? 1u : 0u)
        << run_->models[m].name;
  }
}

}  // namespace
}  // namespace softbench
