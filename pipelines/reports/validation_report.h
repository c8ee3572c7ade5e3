#ifndef SOFTBENCH_PIPELINES_REPORTS_VALIDATION_REPORT_H_
#define SOFTBENCH_PIPELINES_REPORTS_VALIDATION_REPORT_H_

#include <string>

#include "pipelines/formats/test_plan.h"
#include "pipelines/measurement/video_measurement.h"
#include "pipelines/validation/validation.h"

namespace softbench {

// Millimetres as the report files write them (4 decimals; empty for NaN).
std::string FormatMm(double value);

// report.html of one video: the summary, figs. 4.8/4.9 (4.16/4.17), the
// trajectories with the windows shaded, annotated crops of each test's
// windows, the test, hysteresis and repeat tables and the calibration.
std::string ValidationReportHtml(const TestPlan& plan,
                                 const VideoMeasurement& measurement,
                                 const ValidationResult& result);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_REPORTS_VALIDATION_REPORT_H_
