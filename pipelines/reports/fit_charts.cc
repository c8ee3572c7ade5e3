#include "pipelines/reports/fit_charts.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "model/units.h"
#include "pipelines/reports/html_report.h"

namespace softbench {

using nlohmann::json;

// Figs. 3.13/3.14 style: measured force against pressure per configuration
// (up and down ramps) with every fitted model's line.
json ForcePressureChart(const FitRun& run,
                        const std::vector<FitPressureBin>& bins,
                        int direction) {
  json values = json::array();
  for (const FitPressureBin& bin : bins) {
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
json ResidualChart(const FitRun& run, const std::vector<FitPressureBin>& bins) {
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
    for (const FitPressureBin& bin : bins) {
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

}  // namespace softbench
