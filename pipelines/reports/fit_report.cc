#include "pipelines/reports/fit_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "model/units.h"
#include "pipelines/reports/html_report.h"
#include "util/atomic_file.h"
#include "util/csv.h"

namespace softbench {
namespace {

using nlohmann::json;

constexpr std::array<const char*, 2> kDirectionNames = {"axial", "shear"};
constexpr std::array<const char*, kNumFitConstants> kConstantUnits = {
    "mm2", "mm2_per_rad", "n_per_mm", "n_per_rad"};

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

std::string ModelsCsv(const FitRun& run) {
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

std::string ConfigurationsCsv(const FitRun& run) {
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

std::string TestsCsv(const FitRun& run) {
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

// Per test, ramp phase and pressure bin: the measured means, and each
// fitted model's residual mean and spread there (exact from the moments).
struct BinRow {
  int test;
  int phase;
  size_t bin;
  ForceMoments moments;
};

std::vector<BinRow> Bins(const FitRun& run) {
  std::vector<BinRow> bins;
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

std::string PressureBinsCsv(const FitRun& run,
                            const std::vector<BinRow>& bins) {
  std::string out = "test_id,phase,pressure_" + run.pressure_unit +
                    ",rows,axial_n,shear_n,axial_sd_n,shear_sd_n\n";
  for (const BinRow& bin : bins) {
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
    model["method"] = fit.method;
    model["condition_number"] = JsonNumber(fit.condition_number);
    model["at_bounds"] = fit.at_bounds;
    if (fit.ok) {
      const Eigen::Vector4d values = ConstantsVector(fit.constants);
      for (int i = 0; i < kNumFitConstants; ++i) {
        model["constants"][kFitConstantNames[i]] = {
            {"value", values[i]},
            {"standard_error", JsonNumber(fit.standard_errors[i])},
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

// Figs. 3.13/3.14 style: measured force against pressure per configuration
// (up and down ramps) with every fitted model's line.
json ForcePressureChart(const FitRun& run, const std::vector<BinRow>& bins,
                        int direction) {
  json values = json::array();
  for (const BinRow& bin : bins) {
    const ForceTest& test = run.tests[bin.test];
    values.push_back(
        {{"configuration", TestConfigurationName(test)},
         {"series", bin.phase == 0 ? "measured, up" : "measured, down"},
         {"pressure", bin.moments.mean[0] / run.mpa_per_unit},
         {"force", bin.moments.mean[1 + direction]}});
  }
  for (const ConfigurationAnalysis& c : run.configurations) {
    double top = 0.0;
    for (int t : c.tests) {
      top = std::max(top, run.tests[t].statistics.max_pressure_mpa);
    }
    for (size_t m = 0; m < run.models.size(); ++m) {
      if (!run.fits[m].ok) continue;
      const ForceModel model = FittedModel(run.models[m], run.fits[m]);
      for (double p : {0.0, top}) {
        values.push_back(
            {{"configuration", ConfigurationName(c.nominal_delta_length_mm,
                                                 c.nominal_theta_rad)},
             {"series", run.models[m].name},
             {"pressure", p / run.mpa_per_unit},
             {"force", ModelForce(model, p, c.delta_length_mm,
                                  c.theta_rad)[direction]}});
      }
    }
  }
  const std::string unit = run.pressure_unit;
  const json x = {{"field", "pressure"},
                  {"type", "quantitative"},
                  {"title", "pressure [" + unit + "]"}};
  const json y = {
      {"field", "force"},
      {"type", "quantitative"},
      {"title", std::string(kDirectionNames[direction]) + " force [N]"},
      {"scale", {{"zero", false}}}};
  const json color = {{"field", "series"}, {"type", "nominal"}};
  return {
      {"$schema", kVegaLiteSchema},
      {"title", std::string(direction == 0 ? "Axial" : "Shear") +
                    " force against pressure, per configuration"},
      {"data", {{"values", values}}},
      {"facet",
       {{"field", "configuration"}, {"type", "nominal"}, {"title", nullptr}}},
      {"columns", 5},
      {"resolve", {{"scale", {{"y", "independent"}}}}},
      {"spec",
       {{"width", 170},
        {"height", 120},
        {"layer",
         {{{"transform",
            {{{"filter", "indexof(datum.series, 'measured') == 0"}}}},
           {"mark", {{"type", "point"}, {"size", 12}, {"filled", true}}},
           {"encoding", {{"x", x}, {"y", y}, {"color", color}}}},
          {{"transform",
            {{{"filter", "indexof(datum.series, 'measured') != 0"}}}},
           {"mark", {{"type", "line"}, {"strokeWidth", 1}}},
           {"encoding", {{"x", x}, {"y", y}, {"color", color}}}}}}}}};
}

// Fig. 3.18: static offsets, axial against shear, with the model's grid of
// constant dL and constant theta; figs. 3.15/3.16 as the grid's projections.
// (One Vega-Lite specification, written as one declarative value: split
// into pieces it would read worse.)
json StaticOffsetChart(const FitRun& run, const ForceFitSummary& fit,
                       const FitModel& fit_model) {
  json values = json::array();
  for (const ConfigurationAnalysis& c : run.configurations) {
    values.push_back({{"series", "measured"},
                      {"shear", c.static_offset_n[1]},
                      {"axial", c.static_offset_n[0]},
                      {"dL", c.nominal_delta_length_mm},
                      {"theta", RadToDeg(c.nominal_theta_rad)},
                      {"line", ""}});
  }
  const ForceModel model = FittedModel(fit_model, fit);
  std::vector<double> lengths, angles;
  for (const ConfigurationAnalysis& c : run.configurations) {
    if (std::find(lengths.begin(), lengths.end(), c.nominal_delta_length_mm) ==
        lengths.end()) {
      lengths.push_back(c.nominal_delta_length_mm);
    }
    if (std::find(angles.begin(), angles.end(), c.nominal_theta_rad) ==
        angles.end()) {
      angles.push_back(c.nominal_theta_rad);
    }
  }
  std::sort(lengths.begin(), lengths.end());
  std::sort(angles.begin(), angles.end());
  // Lines of constant dL across theta, then of constant theta across dL.
  int order = 0;
  const auto grid_point = [&](double dl, double theta, std::string line) {
    const Eigen::Vector2d f = ModelForce(model, 0.0, dl, theta);
    values.push_back({{"series", "model grid"},
                      {"shear", f[1]},
                      {"axial", f[0]},
                      {"dL", dl},
                      {"theta", RadToDeg(theta)},
                      {"line", std::move(line)},
                      {"order", order++}});
  };
  for (double dl : lengths) {
    for (double theta : angles)
      grid_point(dl, theta, fmt::format("dL {:g}", dl));
  }
  for (double theta : angles) {
    for (double dl : lengths) {
      grid_point(dl, theta, fmt::format("theta {:g}", RadToDeg(theta)));
    }
  }
  return {
      {"$schema", kVegaLiteSchema},
      {"title", "Static offsets at zero pressure: measured and the " +
                    fit.model_name + " model's grid (fig. 3.18)"},
      {"width", 520},
      {"height", 380},
      {"data", {{"values", values}}},
      {"layer",
       {{{"transform", {{{"filter", "datum.series == 'model grid'"}}}},
         {"mark", {{"type", "line"}, {"color", "#999"}, {"strokeWidth", 1}}},
         {"encoding",
          {{"x",
            {{"field", "shear"},
             {"type", "quantitative"},
             {"title", "shear static offset [N]"}}},
           {"y",
            {{"field", "axial"},
             {"type", "quantitative"},
             {"title", "axial static offset [N]"}}},
           {"detail", {{"field", "line"}}},
           {"order", {{"field", "order"}}}}}},
        {{"transform", {{{"filter", "datum.series == 'measured'"}}}},
         {"mark", {{"type", "point"}, {"filled", true}, {"size", 50}}},
         {"encoding",
          {{"x", {{"field", "shear"}, {"type", "quantitative"}}},
           {"y", {{"field", "axial"}, {"type", "quantitative"}}},
           {"color",
            {{"field", "theta"},
             {"type", "ordinal"},
             {"title", "theta [deg]"}}},
           {"shape",
            {{"field", "dL"}, {"type", "nominal"}, {"title", "dL [mm]"}}},
           {"tooltip",
            {{{"field", "dL"}},
             {{"field", "theta"}},
             {{"field", "axial"}},
             {{"field", "shear"}}}}}}}}}};
}

// Figs. 3.15 / 3.16: static offsets against dL and against theta, measured
// per configuration, with the model's lines through the other variable's
// nominal values.
// (One Vega-Lite specification, written as one declarative value: split
// into pieces it would read worse.)
json StaticOffsetProjectionChart(const FitRun& run, const ForceFitSummary& fit,
                                 const FitModel& fit_model) {
  const ForceModel model = FittedModel(fit_model, fit);
  std::vector<double> lengths, angles;
  for (const ConfigurationAnalysis& c : run.configurations) {
    lengths.push_back(c.nominal_delta_length_mm);
    angles.push_back(c.nominal_theta_rad);
  }
  for (std::vector<double>* values : {&lengths, &angles}) {
    std::sort(values->begin(), values->end());
    values->erase(std::unique(values->begin(), values->end()), values->end());
  }
  json values = json::array();
  const auto add = [&](const std::string& series, double dl, double theta,
                       const Eigen::Vector2d& force) {
    for (int d = 0; d < 2; ++d) {
      values.push_back({{"series", series},
                        {"direction", kDirectionNames[d]},
                        {"against", "dL [mm]"},
                        {"x", dl},
                        {"group", fmt::format("theta {:g}", RadToDeg(theta))},
                        {"force", force[d]}});
      values.push_back({{"series", series},
                        {"direction", kDirectionNames[d]},
                        {"against", "theta [deg]"},
                        {"x", RadToDeg(theta)},
                        {"group", fmt::format("dL {:g}", dl)},
                        {"force", force[d]}});
    }
  };
  for (const ConfigurationAnalysis& c : run.configurations) {
    add("measured", c.nominal_delta_length_mm, c.nominal_theta_rad,
        c.static_offset_n);
  }
  for (double dl : lengths) {
    for (double theta : angles) {
      add("model", dl, theta, ModelForce(model, 0.0, dl, theta));
    }
  }
  const json x = {{"field", "x"}, {"type", "quantitative"}, {"title", nullptr}};
  const json y = {{"field", "force"},
                  {"type", "quantitative"},
                  {"title", "static offset [N]"}};
  const json color = {
      {"field", "group"}, {"type", "nominal"}, {"title", nullptr}};
  return {
      {"$schema", kVegaLiteSchema},
      {"title", "Static offsets against dL and theta: measured (points) and " +
                    fit.model_name + " model (lines) (figs. 3.15, 3.16)"},
      {"data", {{"values", values}}},
      {"facet",
       {{"row", {{"field", "direction"}, {"type", "nominal"}}},
        {"column", {{"field", "against"}, {"type", "nominal"}}}}},
      {"resolve", {{"scale", {{"x", "independent"}, {"y", "independent"}}}}},
      {"spec",
       {{"width", 320},
        {"height", 200},
        {"layer",
         {{{"transform", {{{"filter", "datum.series == 'model'"}}}},
           {"mark", {{"type", "line"}, {"strokeWidth", 1}}},
           {"encoding", {{"x", x}, {"y", y}, {"color", color}}}},
          {{"transform", {{{"filter", "datum.series == 'measured'"}}}},
           {"mark", {{"type", "point"}, {"filled", true}}},
           {"encoding", {{"x", x}, {"y", y}, {"color", color}}}}}}}}};
}

// Fig. 3.17: effective areas against theta, with the fitted A_z and W_y
// theta.
json EffectiveAreaChart(const FitRun& run, const ForceFitSummary& fit) {
  json values = json::array();
  double max_theta = 0.0;
  for (const ConfigurationAnalysis& c : run.configurations) {
    const double theta = RadToDeg(c.nominal_theta_rad);
    max_theta = std::max(max_theta, c.theta_rad);
    values.push_back({{"theta", theta},
                      {"area", c.axial_area_mm2},
                      {"panel", "axial A_z,eff"},
                      {"series", "measured"},
                      {"dL", c.nominal_delta_length_mm}});
    values.push_back({{"theta", theta},
                      {"area", c.shear_area_mm2},
                      {"panel", "shear A_y,eff"},
                      {"series", "measured"},
                      {"dL", c.nominal_delta_length_mm}});
  }
  for (double theta : {0.0, max_theta}) {
    values.push_back({{"theta", RadToDeg(theta)},
                      {"area", fit.constants.axial_area_mm2},
                      {"panel", "axial A_z,eff"},
                      {"series", "fit"}});
    values.push_back(
        {{"theta", RadToDeg(theta)},
         {"area", fit.constants.shear_area_factor_mm2_per_rad * theta},
         {"panel", "shear A_y,eff"},
         {"series", "fit"}});
  }
  const json x = {{"field", "theta"},
                  {"type", "quantitative"},
                  {"title", "nominal theta [deg]"}};
  const json y = {{"field", "area"},
                  {"type", "quantitative"},
                  {"title", "effective area [mm^2]"}};
  return {
      {"$schema", kVegaLiteSchema},
      {"title",
       "Effective areas against theta, " + fit.model_name + " fit (fig. 3.17)"},
      {"data", {{"values", values}}},
      {"facet", {{"field", "panel"}, {"type", "nominal"}, {"title", nullptr}}},
      {"resolve", {{"scale", {{"y", "independent"}}}}},
      {"spec",
       {{"width", 320},
        {"height", 240},
        {"layer",
         {{{"transform", {{{"filter", "datum.series == 'measured'"}}}},
           {"mark", {{"type", "point"}, {"filled", true}}},
           {"encoding",
            {{"x", x},
             {"y", y},
             {"shape",
              {{"field", "dL"}, {"type", "nominal"}, {"title", "dL [mm]"}}}}}},
          {{"transform", {{{"filter", "datum.series == 'fit'"}}}},
           {"mark",
            {{"type", "line"}, {"strokeDash", {6, 3}}, {"color", "black"}}},
           {"encoding", {{"x", x}, {"y", y}}}}}}}}};
}

// Residuals by pressure, per model and direction: mean and spread per
// configuration and pressure bin (repeats and both ramps pooled), exact from
// the moments. Shows where in the ramp each model misses.
// (One Vega-Lite specification, written as one declarative value: split
// into pieces it would read worse.)
json ResidualChart(const FitRun& run, const std::vector<BinRow>& bins) {
  struct Pool {
    double rows = 0.0, pressure = 0.0, sum = 0.0, sum_squares = 0.0;
  };
  json values = json::array();
  for (size_t m = 0; m < run.models.size(); ++m) {
    if (!run.fits[m].ok) continue;
    const ForceModel model = FittedModel(run.models[m], run.fits[m]);
    const Eigen::Vector4d c = ConstantsVector(model.constants);
    // [direction][(configuration, bin)]
    std::array<std::map<std::pair<std::string, size_t>, Pool>, 2> pools;
    for (const BinRow& bin : bins) {
      const ForceTest& test = run.tests[bin.test];
      const TestDesign design =
          DesignOfTest(model, test.delta_length_mm(), test.theta_rad());
      const ForceMoments& mo = bin.moments;
      const double n = static_cast<double>(mo.count);
      for (int d = 0; d < 2; ++d) {
        const ResidualMoments r = ResidualsOf(mo, design, d, c);
        Pool& pool = pools[d][{TestConfigurationName(test), bin.bin}];
        pool.rows += n;
        pool.pressure += n * mo.mean[0];
        pool.sum += n * r.mean_n;
        pool.sum_squares += r.SumOfSquares(mo.count);
      }
    }
    for (int d = 0; d < 2; ++d) {
      for (const auto& [key, pool] : pools[d]) {
        const double mean = pool.sum / pool.rows;
        values.push_back(
            {{"model", run.models[m].name},
             {"direction", kDirectionNames[d]},
             {"configuration", key.first},
             {"pressure", pool.pressure / pool.rows / run.mpa_per_unit},
             {"residual", mean},
             {"rows", pool.rows},
             {"sd", std::sqrt(std::max(
                        0.0, pool.sum_squares / pool.rows - mean * mean))}});
      }
    }
  }
  return {{"$schema", kVegaLiteSchema},
          {"title",
           "Residuals (measured - model) by pressure: mean per "
           "configuration and pressure bin; hover for the spread"},
          {"data", {{"values", values}}},
          {"facet",
           {{"row", {{"field", "direction"}, {"type", "nominal"}}},
            {"column", {{"field", "model"}, {"type", "nominal"}}}}},
          {"spec",
           {{"width", 220},
            {"height", 160},
            {"mark",
             {{"type", "line"}, {"strokeWidth", 1}, {"point", {{"size", 8}}}}},
            {"encoding",
             {{"x",
               {{"field", "pressure"},
                {"type", "quantitative"},
                {"title", "pressure [" + run.pressure_unit + "]"}}},
              {"y",
               {{"field", "residual"},
                {"type", "quantitative"},
                {"title", "residual [N]"}}},
              {"color",
               {{"field", "configuration"},
                {"type", "nominal"},
                {"legend", nullptr}}},
              {"tooltip",
               {{{"field", "configuration"}},
                {{"field", "residual"}},
                {{"field", "sd"}},
                {{"field", "rows"}}}}}}}},
          {"resolve", {{"scale", {{"y", "independent"}}}}}};
}

// Distribution of per-test RMS residuals, per model and direction.
json TestRmseChart(const FitRun& run) {
  json values = json::array();
  for (size_t m = 0; m < run.models.size(); ++m) {
    if (!run.fits[m].ok) continue;
    for (size_t t = 0; t < run.tests.size(); ++t) {
      for (int d = 0; d < 2; ++d) {
        values.push_back(
            {{"model", run.models[m].name},
             {"direction", kDirectionNames[d]},
             {"test", run.tests[t].id},
             {"configuration", TestConfigurationName(run.tests[t])},
             {"rmse", run.fits[m].test_rmse_n[t][d]}});
      }
    }
  }
  return {
      {"$schema", kVegaLiteSchema},
      {"title", "RMS residual per test"},
      {"data", {{"values", values}}},
      {"facet", {{"column", {{"field", "direction"}, {"type", "nominal"}}}}},
      {"spec",
       {{"width", 360},
        {"height", 200},
        {"mark", {{"type", "boxplot"}, {"extent", "min-max"}}},
        {"encoding",
         {{"x", {{"field", "model"}, {"type", "nominal"}}},
          {"y",
           {{"field", "rmse"},
            {"type", "quantitative"},
            {"title", "RMS residual [N]"}}},
          {"tooltip", {{{"field", "test"}}, {{"field", "configuration"}}}}}}}},
      {"resolve", {{"scale", {{"y", "independent"}}}}}};
}

std::string Fixed(double value, int digits) {
  return std::isfinite(value) ? fmt::format("{:.{}f}", value, digits) : "-";
}

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
      row.push_back(Fixed(d.r_squared, 4));
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
         std::to_string(c.tests.size()), Fixed(c.static_offset_n[0], 3),
         Fixed(c.static_offset_n[1], 3), Fixed(c.axial_area_mm2, 1),
         Fixed(c.shear_area_mm2, 1), Fixed(c.hysteresis_max_n[0], 3),
         Fixed(c.hysteresis_max_n[1], 3), Fixed(c.hysteresis_mean_n[0], 3),
         Fixed(c.hysteresis_mean_n[1], 3)});
  }
  report->AddTable({"configuration", "tests", "static axial [N]",
                    "static shear [N]", "A_z,eff [mm²]", "A_y,eff [mm²]",
                    "hysteresis axial max [N]", "hysteresis shear max [N]",
                    "hysteresis axial mean [N]", "hysteresis shear mean [N]"},
                   table);
}

std::string ReportHtml(const FitRun& run, const std::vector<BinRow>& bins) {
  HtmlReport report("Actuator characterisation: " + run.input_path);
  report.AddParagraph(fmt::format(
      "{} tests, {} rows ({} skipped) in {:.1f} s. Models of thesis section "
      "3.3 fitted to all rows (Algorithm 1); standard errors assume "
      "independent rows with one noise level per direction.",
      run.tests.size(), run.read.rows, run.read.rows_skipped, run.seconds));
  for (const std::string& example : run.read.skipped_examples) {
    report.AddParagraph("skipped " + example);
  }
  report.AddHeading("Fitted constants and goodness of fit");
  AddConstantsTable(run, &report);
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
  return out;
}

void WriteFitReport(const FitRun& run, const std::string& directory) {
  const std::vector<BinRow> bins = Bins(run);
  // The page first: it is the part that can fail (missing assets).
  const std::string html = ReportHtml(run, bins);
  AtomicDirectory report(directory);
  WriteFileAtomically(report.File("report.html"), html);
  WriteFileAtomically(
      report.File("fit.json"),
      FitJson(run).dump(2, ' ', false, json::error_handler_t::replace) + "\n");
  WriteFileAtomically(report.File("models.csv"), ModelsCsv(run));
  WriteFileAtomically(report.File("configurations.csv"),
                      ConfigurationsCsv(run));
  WriteFileAtomically(report.File("tests.csv"), TestsCsv(run));
  WriteFileAtomically(report.File("pressure_bins.csv"),
                      PressureBinsCsv(run, bins));
  report.Commit();
}

}  // namespace softbench
