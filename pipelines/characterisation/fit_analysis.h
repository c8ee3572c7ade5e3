#ifndef SOFTBENCH_PIPELINES_CHARACTERISATION_FIT_ANALYSIS_H_
#define SOFTBENCH_PIPELINES_CHARACTERISATION_FIT_ANALYSIS_H_

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "calibration/force_analysis.h"
#include "calibration/force_fit.h"
#include "calibration/force_log_reader.h"
#include "pipelines/characterisation/force_log_manifest.h"

namespace softbench {

// The characterisation of thesis chapter 3 (Algorithm 1): every variant and
// the baseline fitted to a set of force-sensor logs, with the per-
// configuration analysis.
struct FitAnalysisOptions {
  // A manifest (.yaml) or a combined log (.csv; then `combined_columns`).
  std::string input_path;
  // The columns of a combined CSV read without a manifest.
  ForceLogColumns combined_columns;
  // Loss, weights and bounds of every model's fit.
  ForceFitOptions fit;
  // Rows kept in memory for a robust fit (evenly spaced over the logs).
  int64_t robust_rows = 1000000;
  // L0 of the variable-arm variant (Eq. 3.3) [mm].
  double natural_length_mm = 18.5;
  int threads = 0;       // files read at once (0: one per core)
  bool progress = true;  // report progress (util/progress.h) while reading
  // The logs' decimal mark, as the user declared it (--decimal-comma).
  DecimalMark decimal_mark = DecimalMark::kPoint;

  // The first bad field, named, and what it must be.
  std::optional<std::string> Problem() const;
};

// Everything the analysis found: the tests, how reading went, every model's
// fit and the per-configuration analysis.
struct FitRun {
  std::string input_path;
  std::vector<ForceTest> tests;
  ForceLogReadSummary read;
  std::vector<FitModel> models;
  std::vector<ForceFitSummary> fits;  // one per model, same order
  std::vector<ConfigurationAnalysis> configurations;
  double mpa_per_unit = 0.001;  // the log's pressure unit, for tables
  std::string pressure_unit = "kpa";
  double seconds = 0.0;
  // For people: rows skipped while reading (with examples).
  std::vector<std::string> warnings;
};

// Reads the logs and fits every model. Throws InputError for unreadable
// inputs; a model that cannot be fitted says why in its summary.
FitRun RunFitAnalysis(const FitAnalysisOptions& options);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_CHARACTERISATION_FIT_ANALYSIS_H_
