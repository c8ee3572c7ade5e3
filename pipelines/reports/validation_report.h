#ifndef SOFTBENCH_PIPELINES_REPORTS_VALIDATION_REPORT_H_
#define SOFTBENCH_PIPELINES_REPORTS_VALIDATION_REPORT_H_

#include <string>

#include "pipelines/validation/validate_video.h"

namespace softbench {

// Millimetres as the report files write them (4 decimals; empty for NaN).
std::string FormatMm(double value);
// An uncertainty in millimetres, to a hundredth of a micrometre.
std::string FormatMicrons(double value_mm);
// A percentage as the report pages show it ("12 %"; empty for NaN).
std::string FormatPercent(double value);

// The files written beside report.html, which it links to.
inline constexpr const char* kValidationFiles[] = {
    "results.csv", "summary.json", "trajectory.csv"};

// report.html of one video: links to the files beside it, the summary with
// each head's uncertainty, figs. 4.8/4.9 (4.16/4.17) with equal axes where
// positions are drawn, the trajectories with the windows shaded, annotated
// crops of each test's windows, the test table (pressures and unit,
// uncertainty and frames), hysteresis and repeat tables, the calibration and
// the inputs with their SHA-256.
std::string ValidationReportHtml(const VideoValidation& validation);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_REPORTS_VALIDATION_REPORT_H_
