#include "pipelines/reports/fit_files.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "model/units.h"
#include "pipelines/reports/html_report.h"
#include "util/csv.h"

namespace softbench {

using nlohmann::json;

namespace {

constexpr std::array<const char*, kNumFitConstants> kConstantUnits = {
    "mm2", "mm2_per_rad", "n_per_mm", "n_per_rad"};

}  // namespace

std::string ConfigurationName(double delta_length_mm, double theta_rad) {
  return fmt::format("dL {:+g} mm, theta {:g} deg", delta_length_mm,
                     std::round(RadToDeg(theta_rad) * 100.0) / 100.0);
}

std::string TestConfigurationName(const ForceTest& test) {
  return ConfigurationName(test.nominal_delta_length_mm,
                           test.nominal_theta_rad);
}

// The model's force in each direction at pressure P for a configuration.
Eigen::Vector2d ModelForce(const ForceModel& model, double pressure_mpa,
                           double delta_length_mm, double theta_rad) {
  const Eigen::Vector2d local =
      EvaluateActuatorForce(model, pressure_mpa, {delta_length_mm, theta_rad})
          .force_in_local_n;
  return {local[1], local[0]};
}

ForceModel FittedModel(const FitModel& model, const ForceFitSummary& fit) {
  ForceModel fitted = model.model;
  fitted.constants = fit.constants;
  return fitted;
}

std::string FitModelsCsv(const FitRun& run) {
  std::string out = "model,status,method";
  for (int i = 0; i < kNumFitConstants; ++i) {
    out += fmt::format(",{0}_{1},{0}_se_{1}", kFitConstantNames[i],
                       kConstantUnits[i]);
  }
  for (const char* d : kDirectionNames) {
    out +=
        fmt::format(",{0}_r2,{0}_rmse_n,{0}_full_scale_n,{0}_rmse_pct_fsr", d);
  }
  out += ",rows,condition_number,why_not\n";
  for (const ForceFitSummary& fit : run.fits) {
    out += fmt::format("{},{},\"{}\"", fit.model_name, fit.ok ? "ok" : "failed",
                       fit.method);
    const Eigen::Vector4d values = ConstantsVector(fit.constants);
    for (int i = 0; i < kNumFitConstants; ++i) {
      out += fit.ok ? fmt::format(",{:.10g},{:.4g}", values[i],
                                  fit.standard_errors[i])
                    : std::string(",,");
    }
    for (const DirectionFit& d : fit.directions) {
      out += fit.ok ? fmt::format(",{:.6f},{:.6f},{:.6f},{:.4f}", d.r_squared,
                                  d.rmse_n, d.full_scale_range_n,
                                  d.rmse_percent_of_range)
                    : std::string(",,,,");
    }
    out += fmt::format(",{},{:.4g},\"{}\"\n", fit.rows, fit.condition_number,
                       fit.why_not);
  }
  return out;
}

std::string FitConfigurationsCsv(const FitRun& run) {
  std::string out =
      "nominal_delta_length_mm,nominal_theta_deg,delta_length_mm,theta_deg,"
      "tests,static_axial_n,static_shear_n,static_axial_spread_n,"
      "static_shear_spread_n";
  for (const FitModel& model : run.models) {
    out += fmt::format(",{0}_static_axial_n,{0}_static_shear_n", model.name);
  }
  for (const FitModel& model : run.models) {
    out += fmt::format(",{0}_axial_rmse_n,{0}_shear_rmse_n", model.name);
  }
  out +=
      ",axial_area_mm2,shear_area_mm2,hysteresis_axial_max_n,"
      "hysteresis_shear_max_n,hysteresis_axial_mean_n,hysteresis_shear_mean_n"
      "\n";
  for (const ConfigurationAnalysis& c : run.configurations) {
    out +=
        fmt::format("{:g},{:g},{:.4f},{:.4f},{},{:.5f},{:.5f},{:.5f},{:.5f}",
                    c.nominal_delta_length_mm, RadToDeg(c.nominal_theta_rad),
                    c.delta_length_mm, RadToDeg(c.theta_rad), c.tests.size(),
                    c.static_offset_n[0], c.static_offset_n[1],
                    c.static_offset_spread_n[0], c.static_offset_spread_n[1]);
    for (size_t m = 0; m < run.models.size(); ++m) {
      if (!run.fits[m].ok) {
        out += ",,";
        continue;
      }
      const Eigen::Vector2d model =
          ModelForce(FittedModel(run.models[m], run.fits[m]), 0.0,
                     c.delta_length_mm, c.theta_rad);
      out += fmt::format(",{:.5f},{:.5f}", model[0], model[1]);
    }
    for (const ForceFitSummary& fit : run.fits) {
      // Pooled over the repeats: sqrt(sum n rmse^2 / sum n).
      Eigen::Vector2d squares = Eigen::Vector2d::Zero();
      double rows = 0.0;
      for (int t : c.tests) {
        if (!fit.ok) break;
        const double n =
            static_cast<double>(run.tests[t].statistics.All().count);
        rows += n;
        for (int d = 0; d < 2; ++d) {
          squares[d] += n * fit.test_rmse_n[t][d] * fit.test_rmse_n[t][d];
        }
      }
      out += fit.ok
                 ? fmt::format(",{:.5f},{:.5f}", std::sqrt(squares[0] / rows),
                               std::sqrt(squares[1] / rows))
                 : std::string(",,");
    }
    out += fmt::format(",{:.4f},{:.4f},{:.5f},{:.5f},{:.5f},{:.5f}\n",
                       c.axial_area_mm2, c.shear_area_mm2,
                       c.hysteresis_max_n[0], c.hysteresis_max_n[1],
                       c.hysteresis_mean_n[0], c.hysteresis_mean_n[1]);
  }
  return out;
}

std::string FitTestsCsv(const FitRun& run) {
  std::string out =
      "test_id,source,nominal_delta_length_mm,nominal_theta_deg,"
      "delta_length_mm,theta_deg,rows,zero_pressure_rows,max_pressure_" +
      run.pressure_unit;
  for (const FitModel& model : run.models) {
    out += fmt::format(",{0}_axial_rmse_n,{0}_shear_rmse_n", model.name);
  }
  out += "\n";
  for (size_t t = 0; t < run.tests.size(); ++t) {
    const ForceTest& test = run.tests[t];
    out += fmt::format("{},{},{:g},{:g},{:.4f},{:.4f},{},{},{:.4f}",
                       CsvField(test.id), CsvField(test.source),
                       test.nominal_delta_length_mm,
                       RadToDeg(test.nominal_theta_rad), test.delta_length_mm(),
                       RadToDeg(test.theta_rad()), test.statistics.All().count,
                       test.statistics.ZeroPressure().count,
                       test.statistics.max_pressure_mpa / run.mpa_per_unit);
    for (const ForceFitSummary& fit : run.fits) {
      out += fit.ok ? fmt::format(",{:.5f},{:.5f}", fit.test_rmse_n[t][0],
                                  fit.test_rmse_n[t][1])
                    : std::string(",,");
    }
    out += "\n";
  }
  return out;
}

std::vector<FitPressureBin> FitPressureBins(const FitRun& run) {
  std::vector<FitPressureBin> bins;
  for (int t = 0; t < static_cast<int>(run.tests.size()); ++t) {
    for (int phase = 0; phase < kNumRampPhases; ++phase) {
      const std::vector<ForceMoments>& moments =
          run.tests[t].statistics.bins[phase];
      for (size_t b = 0; b < moments.size(); ++b) {
        if (moments[b].count > 0) bins.push_back({t, phase, b, moments[b]});
      }
    }
  }
  return bins;
}

std::string FitPressureBinsCsv(const FitRun& run,
                               const std::vector<FitPressureBin>& bins) {
  std::string out = "test_id,phase,pressure_" + run.pressure_unit +
                    ",rows,axial_n,shear_n,axial_sd_n,shear_sd_n\n";
  for (const FitPressureBin& bin : bins) {
    const ForceMoments& m = bin.moments;
    const double n = static_cast<double>(m.count);
    out += fmt::format(
        "{},{},{:.5f},{},{:.5f},{:.5f},{:.5f},{:.5f}\n",
        CsvField(run.tests[bin.test].id), bin.phase == 0 ? "up" : "down",
        m.mean[0] / run.mpa_per_unit, m.count, m.mean[1], m.mean[2],
        std::sqrt(m.comoment(1, 1) / n), std::sqrt(m.comoment(2, 2) / n));
  }
  return out;
}

json FitJson(const FitRun& run) {
  json root;
  root["input"] = run.input_path;
  root["seconds"] = run.seconds;
  root["rows"] = run.read.rows;
  root["rows_skipped"] = run.read.rows_skipped;
  root["skipped_examples"] = run.read.skipped_examples;
  root["pressure_unit"] = run.pressure_unit;
  for (const ForceFitSummary& fit : run.fits) {
    json model;
    model["name"] = fit.model_name;
    model["ok"] = fit.ok;
    model["why_not"] = fit.why_not;
    model["standard_errors_caveat"] =
        fit.standard_errors_caveat ? json(*fit.standard_errors_caveat) : json();
    model["method"] = fit.method;
    model["condition_number"] = JsonNumber(fit.condition_number);
    model["at_bounds"] = fit.at_bounds;
    if (fit.ok) {
      const Eigen::Vector4d values = ConstantsVector(fit.constants);
      for (int i = 0; i < kNumFitConstants; ++i) {
        model["constants"][kFitConstantNames[i]] = {
            {"value", values[i]},
            {"standard_error", JsonNumber(fit.standard_errors[i])},
            {"row_noise_standard_error",
             JsonNumber(fit.row_noise_standard_errors[i])},
            {"unit", kConstantUnits[i]}};
      }
      model["natural_length_mm"] = fit.constants.natural_length_mm;
      for (int d = 0; d < 2; ++d) {
        const DirectionFit& f = fit.directions[d];
        model[kDirectionNames[d]] = {
            {"r_squared", f.r_squared},
            {"rmse_n", f.rmse_n},
            {"full_scale_range_n", f.full_scale_range_n},
            {"rmse_percent_of_range", f.rmse_percent_of_range}};
      }
    }
    root["models"].push_back(model);
  }
  for (const ConfigurationAnalysis& c : run.configurations) {
    root["configurations"].push_back(
        {{"nominal_delta_length_mm", c.nominal_delta_length_mm},
         {"nominal_theta_deg", RadToDeg(c.nominal_theta_rad)},
         {"static_offset_n", {c.static_offset_n[0], c.static_offset_n[1]}},
         {"axial_area_mm2", c.axial_area_mm2},
         {"shear_area_mm2", c.shear_area_mm2},
         {"hysteresis_max_n", {c.hysteresis_max_n[0], c.hysteresis_max_n[1]}},
         {"hysteresis_mean_n",
          {c.hysteresis_mean_n[0], c.hysteresis_mean_n[1]}}});
  }
  return root;
}

}  // namespace softbench
