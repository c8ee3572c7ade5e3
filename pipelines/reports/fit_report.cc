#include "pipelines/reports/fit_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "model/units.h"
#include "pipelines/reports/fit_charts.h"
#include "pipelines/reports/fit_files.h"
#include "pipelines/reports/html_report.h"
#include "util/atomic_file.h"

namespace softbench {
namespace {

using nlohmann::json;

// What the ± beside each constant is (ForceFitSummary::standard_errors),
// on stdout and in the report alike.
constexpr char kStandardErrorMeaning[] =
    "± is one standard error: the larger of the rows' noise and the tests' "
    "scatter";

// The fitted constants with standard errors and the goodness of fit of
// every model (thesis Table 3.2's terms).
void AddConstantsTable(const FitRun& run, HtmlReport* report) {
  std::vector<std::vector<std::string>> rows;
  for (const ForceFitSummary& fit : run.fits) {
    std::vector<std::string> row = {fit.model_name};
    if (!fit.ok) {
      row.push_back("not fitted: " + fit.why_not);
      rows.push_back(row);
      continue;
    }
    const Eigen::Vector4d values = ConstantsVector(fit.constants);
    for (int i = 0; i < kNumFitConstants; ++i) {
      row.push_back(std::isfinite(fit.standard_errors[i])
                        ? fmt::format("{:.4g} ± {:.2g}", values[i],
                                      fit.standard_errors[i])
                        : fmt::format("{:.4g}", values[i]));
    }
    for (const DirectionFit& d : fit.directions) {
      row.push_back(FormatFixed(d.r_squared, 4, "-"));
      row.push_back(fmt::format("{:.3f} ({:.2f} % of {:.2f})", d.rmse_n,
                                d.rmse_percent_of_range, d.full_scale_range_n));
    }
    row.push_back(fit.method);
    rows.push_back(row);
  }
  report->AddTable({"model", "A_z [mm²]", "W_y [mm²/rad]", "k_s [N/mm]",
                    "k_θ [N/rad]", "axial R²", "axial RMSE [N] (% FSR)",
                    "shear R²", "shear RMSE [N] (% FSR)", "method"},
                   rows);
}

// Per configuration: static offsets, effective areas and hysteresis.
void AddConfigurationTable(const FitRun& run, HtmlReport* report) {
  std::vector<std::vector<std::string>> table;
  for (const ConfigurationAnalysis& c : run.configurations) {
    table.push_back(
        {ConfigurationName(c.nominal_delta_length_mm, c.nominal_theta_rad),
         std::to_string(c.tests.size()),
         FormatFixed(c.static_offset_n[0], 3, "-"),
         FormatFixed(c.static_offset_n[1], 3, "-"),
         FormatFixed(c.axial_area_mm2, 1, "-"),
         FormatFixed(c.shear_area_mm2, 1, "-"),
         FormatFixed(c.hysteresis_max_n[0], 3, "-"),
         FormatFixed(c.hysteresis_max_n[1], 3, "-"),
         FormatFixed(c.hysteresis_mean_n[0], 3, "-"),
         FormatFixed(c.hysteresis_mean_n[1], 3, "-")});
  }
  report->AddTable({"configuration", "tests", "static axial [N]",
                    "static shear [N]", "A_z,eff [mm²]", "A_y,eff [mm²]",
                    "hysteresis axial max [N]", "hysteresis shear max [N]",
                    "hysteresis axial mean [N]", "hysteresis shear mean [N]"},
                   table);
}

std::string ReportHtml(const FitRun& run,
                       const std::vector<FitPressureBin>& bins) {
  HtmlReport report("Actuator characterisation: " + run.input_path);
  report.AddParagraph(fmt::format(
      "{} tests, {} rows ({} skipped) in {:.1f} s. Models of thesis section "
      "3.3 fitted to all rows (Algorithm 1). {}, as the rows of one test "
      "share its clamp and the model's misfit there.",
      run.tests.size(), run.read.rows, run.read.rows_skipped, run.seconds,
      kStandardErrorMeaning));
  for (const std::string& example : run.read.skipped_examples) {
    report.AddParagraph("skipped " + example);
  }
  report.AddHeading("Fitted constants and goodness of fit");
  AddConstantsTable(run, &report);
  for (const ForceFitSummary& fit : run.fits) {
    if (fit.ok && fit.standard_errors_caveat) {
      report.AddParagraph(fit.model_name + ": " + *fit.standard_errors_caveat);
    }
  }
  int chosen = -1;
  for (size_t m = 0; m < run.fits.size(); ++m) {
    if (run.fits[m].ok && chosen < 0) chosen = static_cast<int>(m);
  }
  report.AddHeading("Force against pressure (up and down ramps)");
  report.AddChart(ForcePressureChart(run, bins, 0));
  report.AddChart(ForcePressureChart(run, bins, 1));
  if (chosen >= 0) {
    report.AddHeading("Static offsets");
    report.AddChart(
        StaticOffsetChart(run, run.fits[chosen], run.models[chosen]));
    report.AddChart(
        StaticOffsetProjectionChart(run, run.fits[chosen], run.models[chosen]));
    report.AddHeading("Effective areas");
    report.AddChart(EffectiveAreaChart(run, run.fits[chosen]));
  }
  report.AddHeading("Residuals");
  report.AddChart(ResidualChart(run, bins));
  report.AddChart(TestRmseChart(run));
  report.AddHeading(
      "Configurations and hysteresis (up-ramp line minus down-ramp line)");
  AddConfigurationTable(run, &report);
  return report.Render();
}

}  // namespace

std::string FitTable(const FitRun& run) {
  std::string out = fmt::format("{} tests, {} rows ({} skipped) in {:.2f} s\n",
                                run.tests.size(), run.read.rows,
                                run.read.rows_skipped, run.seconds);
  out +=
      fmt::format("{:<19}{:>20}{:>20}{:>18}{:>18}  {:>26}  {:>26}\n", "model",
                  "A_z mm^2", "W_y mm^2/rad", "k_s N/mm", "k_theta N/rad",
                  "axial R^2, RMSE N (%FSR)", "shear R^2, RMSE N (%FSR)");
  for (const ForceFitSummary& fit : run.fits) {
    if (!fit.ok) {
      out += fmt::format("{:<19}not fitted: {}\n", fit.model_name, fit.why_not);
      continue;
    }
    out += fmt::format("{:<19}", fit.model_name);
    const Eigen::Vector4d values = ConstantsVector(fit.constants);
    const std::array<int, 4> widths = {20, 20, 18, 18};
    for (int i = 0; i < kNumFitConstants; ++i) {
      const std::string cell = std::isfinite(fit.standard_errors[i])
                                   ? fmt::format("{:.4f} ± {:.4f}", values[i],
                                                 fit.standard_errors[i])
                                   : fmt::format("{:.4f}", values[i]);
      out += fmt::format("{:>{}}", cell, widths[i]);
    }
    for (const DirectionFit& d : fit.directions) {
      out += fmt::format("  {:>26}",
                         fmt::format("{:.4f}, {:.3f} ({:.2f} %)", d.r_squared,
                                     d.rmse_n, d.rmse_percent_of_range));
    }
    out += "\n";
  }
  out += std::string(kStandardErrorMeaning) + "\n";
  return out;
}

void WriteFitReport(const FitRun& run, const std::string& directory) {
  const std::vector<FitPressureBin> bins = FitPressureBins(run);
  // The page first: it is the part that can fail (missing assets).
  const std::string html = ReportHtml(run, bins);
  AtomicDirectory report(directory);
  WriteFileAtomically(report.File("report.html"), html);
  WriteFileAtomically(
      report.File("fit.json"),
      FitJson(run).dump(2, ' ', false, json::error_handler_t::replace) + "\n");
  WriteFileAtomically(report.File("models.csv"), FitModelsCsv(run));
  WriteFileAtomically(report.File("configurations.csv"),
                      FitConfigurationsCsv(run));
  WriteFileAtomically(report.File("tests.csv"), FitTestsCsv(run));
  WriteFileAtomically(report.File("pressure_bins.csv"),
                      FitPressureBinsCsv(run, bins));
  report.Commit();
}

}  // namespace softbench