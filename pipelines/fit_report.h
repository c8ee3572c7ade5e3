#ifndef SOFTBENCH_PIPELINES_FIT_REPORT_H_
#define SOFTBENCH_PIPELINES_FIT_REPORT_H_

#include <string>
#include <vector>

#include "calibration/force_analysis.h"
#include "calibration/force_fit.h"
#include "calibration/force_log_reader.h"

namespace softbench {

// Everything `softbench fit` found: the tests, how reading went, every
// model's fit and the per-configuration analysis.
struct FitRun {
  std::string input_path;
  std::vector<ForceTest> tests;
  ForceLogReadSummary read;
  std::vector<FitModel> models;
  std::vector<ForceFitSummary> fits;  // one per model, same order
  std::vector<ConfigurationAnalysis> configurations;
  double pressure_unit_mpa = 0.001;  // the log's pressure unit, for tables
  std::string pressure_unit = "kpa";
  double seconds = 0.0;
};

// The goodness-of-fit table printed by the command (thesis section 3.3's
// terms).
std::string FitTable(const FitRun& run);

// Writes the report directory atomically: fit.json, models.csv,
// configurations.csv, tests.csv, pressure_bins.csv and report.html.
void WriteFitReport(const FitRun& run, const std::string& directory);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_FIT_REPORT_H_
