#ifndef SOFTBENCH_PIPELINES_REPORTS_FIT_CHARTS_H_
#define SOFTBENCH_PIPELINES_REPORTS_FIT_CHARTS_H_

#include <nlohmann/json.hpp>
#include <vector>

#include "pipelines/characterisation/fit_analysis.h"
#include "pipelines/reports/fit_files.h"

namespace softbench {

// The fit report's charts as Vega-Lite specifications (HtmlReport::AddChart),
// after the thesis's figures; each has a title.

// Figs. 3.13/3.14: measured force against pressure per configuration (up and
// down ramps) with every fitted model's line; direction 0 axial, 1 shear.
nlohmann::json ForcePressureChart(const FitRun& run,
                                  const std::vector<FitPressureBin>& bins,
                                  int direction);
// Fig. 3.18: static offsets, axial against shear, with the model's grid.
nlohmann::json StaticOffsetChart(const FitRun& run, const ForceFitSummary& fit,
                                 const FitModel& model);
// Figs. 3.15/3.16: static offsets against dL and against theta.
nlohmann::json StaticOffsetProjectionChart(const FitRun& run,
                                           const ForceFitSummary& fit,
                                           const FitModel& model);
// Fig. 3.17: effective areas against theta.
nlohmann::json EffectiveAreaChart(const FitRun& run,
                                  const ForceFitSummary& fit);
// Residuals by pressure, per model and direction.
nlohmann::json ResidualChart(const FitRun& run,
                             const std::vector<FitPressureBin>& bins);
// Distribution of per-test RMS residuals, per model and direction.
nlohmann::json TestRmseChart(const FitRun& run);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_REPORTS_FIT_CHARTS_H_
