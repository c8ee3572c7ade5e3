#ifndef SOFTBENCH_PIPELINES_REPORTS_FIT_FILES_H_
#define SOFTBENCH_PIPELINES_REPORTS_FIT_FILES_H_

#include <Eigen/Core>
#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pipelines/characterisation/fit_analysis.h"

namespace softbench {

// The files of a fit report (docs/file-formats.md, "Fit report") and what
// its charts share with them.

inline constexpr std::array<const char*, 2> kDirectionNames = {"axial",
                                                               "shear"};

// "dL +1 mm, theta 10 deg": a configuration as the report names it.
std::string ConfigurationName(double delta_length_mm, double theta_rad);
std::string TestConfigurationName(const ForceTest& test);

// The model's force in each direction (axial, shear) at pressure P for a
// configuration.
Eigen::Vector2d ModelForce(const ForceModel& model, double pressure_mpa,
                           double delta_length_mm, double theta_rad);

// `model` with the constants `fit` found.
ForceModel FittedModel(const FitModel& model, const ForceFitSummary& fit);

// Per test, ramp phase and pressure bin: the measured moments, from which
// each fitted model's residual mean and spread there are exact.
struct FitPressureBin {
  int test;
  int phase;
  size_t bin;
  ForceMoments moments;
};
std::vector<FitPressureBin> FitPressureBins(const FitRun& run);

// models.csv: one row per model, its constants with standard errors and
// goodness of fit.
std::string FitModelsCsv(const FitRun& run);
// configurations.csv: per configuration, static offsets, effective areas and
// hysteresis.
std::string FitConfigurationsCsv(const FitRun& run);
// tests.csv: per test, its configuration and each model's RMS residuals.
std::string FitTestsCsv(const FitRun& run);
// pressure_bins.csv: the measured means and spreads per pressure bin.
std::string FitPressureBinsCsv(const FitRun& run,
                               const std::vector<FitPressureBin>& bins);
// fit.json: everything above in one document.
nlohmann::json FitJson(const FitRun& run);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_REPORTS_FIT_FILES_H_
