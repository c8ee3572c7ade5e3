#ifndef SOFTBENCH_PIPELINES_REPORTS_FIT_REPORT_H_
#define SOFTBENCH_PIPELINES_REPORTS_FIT_REPORT_H_

#include <string>
#include <vector>

#include "pipelines/characterisation/fit_analysis.h"

namespace softbench {

// The goodness-of-fit table printed by the command (thesis section 3.3's
// terms).
std::string FitTable(const FitRun& run);

// Writes the report directory atomically: fit.json, models.csv,
// configurations.csv, tests.csv, pressure_bins.csv and report.html.
void WriteFitReport(const FitRun& run, const std::string& directory);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_REPORTS_FIT_REPORT_H_
