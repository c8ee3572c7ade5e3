#include "pipelines/reports/validation_charts.h"

#include <cmath>
#include <numbers>
#include <string>

#include "pipelines/reports/html_report.h"

namespace softbench {

using nlohmann::json;

std::pair<json, json> EqualDomains(const json& values) {
  Eigen::Vector2d low = Eigen::Vector2d::Constant(INFINITY);
  Eigen::Vector2d high = Eigen::Vector2d::Constant(-INFINITY);
  for (const json& v : values) {
    const Eigen::Vector2d p(v["y"].get<double>(), v["z"].get<double>());
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  if (!low.allFinite()) return {json::array({-1, 1}), json::array({-1, 1})};
  const double half =
      std::max(0.55 * (high - low).maxCoeff(), 0.01);  // 10 % margin
  const Eigen::Vector2d centre = (low + high) / 2.0;
  return {json::array({centre.x() - half, centre.x() + half}),
          json::array({centre.y() - half, centre.y() + half})};
}

json PositionChart(const TestPlan& plan, const ValidationResult& r) {
  json values = json::array();
  for (const TestScore& t : r.tests) {
    if (!t.matches_plan) continue;  // not scored: its entry is not its motion
    for (size_t h = 0; h < t.heads.size(); ++h) {
      const HeadScore& s = t.heads[h];
      const std::string head = plan.mechanism.heads[h].name;
      const auto point = [&](const std::string& series,
                             const Eigen::Vector2d& p,
                             const std::string& pair) {
        if (!p.allFinite()) return;
        values.push_back({{"test", t.id},
                          {"head", head},
                          {"series", series},
                          {"y", p.x()},
                          {"z", p.y()},
                          {"pair", pair}});
      };
      point("measured", s.measured_mm, "");
      point(r.model_name, s.model_mm, "");
      point(r.baseline_name, s.baseline_mm, "");
      // Error lines: measured to model, measured to baseline.
      point("error line", s.measured_mm, t.id + "/model");
      point("error line", s.model_mm, t.id + "/model");
      point("error line", s.measured_mm, t.id + "/baseline");
      point("error line", s.baseline_mm, t.id + "/baseline");
      // The measured displacement's U = 2u ellipse (axes along y and z).
      if (!t.scored() || !s.budget.u_mm.allFinite()) continue;
      constexpr int kSides = 24;
      for (int k = 0; k <= kSides; ++k) {
        const double a = 2.0 * std::numbers::pi * k / kSides;
        const Eigen::Vector2d p =
            s.measured_mm +
            2.0 * Eigen::Vector2d(s.budget.u_mm.x() * std::cos(a),
                                  s.budget.u_mm.y() * std::sin(a));
        values.push_back({{"test", t.id},
                          {"head", head},
                          {"series", "U = 2u ellipse"},
                          {"y", p.x()},
                          {"z", p.y()},
                          {"pair", t.id + "/ellipse"},
                          {"k", k}});
      }
    }
  }
  // Equal axes: a square plot whose two domains span the same millimetres,
  // so a circle of positions stays a circle.
  const auto [y_domain, z_domain] = EqualDomains(values);
  const json x = {{"field", "y"},
                  {"type", "quantitative"},
                  {"scale", {{"domain", y_domain}, {"nice", false}}},
                  {"title", "y [mm]"}};
  const json y = {{"field", "z"},
                  {"type", "quantitative"},
                  {"scale", {{"domain", z_domain}, {"nice", false}}},
                  {"title", "z [mm]"}};
  return {
      {"$schema", kVegaLiteSchema},
      {"title",
       "Measured and predicted displacements (figs. 4.8, 4.16), "
       "equal axes; the measured ones' U = 2u ellipses"},
      {"data", {{"values", values}}},
      {"facet", {{"field", "head"}, {"type", "nominal"}}},
      {"spec",
       {{"width", 380},
        {"height", 380},
        {"layer",
         {{{"transform", {{{"filter", "datum.series == 'error line'"}}}},
           {"mark", {{"type", "line"}, {"color", "#bbb"}, {"strokeWidth", 1}}},
           {"encoding", {{"x", x}, {"y", y}, {"detail", {{"field", "pair"}}}}}},
          {{"transform", {{{"filter", "datum.series == 'U = 2u ellipse'"}}}},
           {"mark", {{"type", "line"}, {"color", "#444"}, {"strokeWidth", 1}}},
           {"encoding",
            {{"x", x},
             {"y", y},
             {"detail", {{"field", "pair"}}},
             {"order", {{"field", "k"}, {"type", "quantitative"}}}}}},
          {{"transform",
            {{{"filter",
               "datum.series != 'error line' && "
               "datum.series != 'U = 2u ellipse'"}}}},
           {"mark", {{"type", "point"}, {"filled", true}, {"size", 50}}},
           {"encoding",
            {{"x", x},
             {"y", y},
             {"color", {{"field", "series"}, {"type", "nominal"}}},
             {"shape", {{"field", "series"}, {"type", "nominal"}}},
             {"tooltip",
              {{{"field", "test"}},
               {{"field", "series"}},
               {{"field", "y"}},
               {{"field", "z"}}}}}}}}}}}};
}

json ErrorChart(const TestPlan& plan, const ValidationResult& r) {
  json values = json::array();
  for (const TestScore& t : r.tests) {
    if (!t.matches_plan) continue;  // not scored
    for (size_t h = 0; h < t.heads.size(); ++h) {
      for (const auto& [name, error] :
           {std::pair{r.model_name, t.heads[h].model_error_mm},
            std::pair{r.baseline_name, t.heads[h].baseline_error_mm}}) {
        if (!std::isfinite(error)) continue;
        values.push_back({{"test", t.id},
                          {"head", plan.mechanism.heads[h].name},
                          {"model", name},
                          {"error", error}});
      }
      if (t.scored()) {
        values.push_back({{"test", t.id},
                          {"head", plan.mechanism.heads[h].name},
                          {"model", "U = 2u of the measurement"},
                          {"error", 2.0 * t.heads[h].budget.TotalMm()}});
      }
    }
  }
  const json test_axis = {
      {"field", "test"}, {"type", "nominal"}, {"sort", nullptr}};
  const json error_axis = {{"field", "error"},
                           {"type", "quantitative"},
                           {"title", "|measured - predicted| [mm]"}};
  return {
      {"$schema", kVegaLiteSchema},
      {"title",
       "Position error per test point (figs. 4.9, 4.17), with the "
       "measurement's U = 2u"},
      {"data", {{"values", values}}},
      {"facet", {{"field", "head"}, {"type", "nominal"}}},
      {"spec",
       {{"width", 420},
        {"height", 220},
        {"layer",
         {{{"transform",
            {{{"filter",
               "datum.model != 'U = 2u of the "
               "measurement'"}}}},
           {"mark", "bar"},
           {"encoding",
            {{"x", test_axis},
             {"xOffset", {{"field", "model"}}},
             {"y", error_axis},
             {"color", {{"field", "model"}, {"type", "nominal"}}},
             {"tooltip",
              {{{"field", "test"}},
               {{"field", "model"}},
               {{"field", "error"}}}}}}},
          {{"transform",
            {{{"filter",
               "datum.model == 'U = 2u of the "
               "measurement'"}}}},
           {"mark", {{"type", "tick"}, {"color", "black"}, {"thickness", 2}}},
           {"encoding",
            {{"x", test_axis},
             {"y", error_axis},
             {"tooltip",
              {{{"field", "test"}},
               {{"field", "model"}},
               {{"field", "error"}}}}}}}}}}}};
}

json LiftChart(const TestPlan& plan, const ValidationResult& r) {
  json values = json::array();
  for (const TestScore& t : r.tests) {
    if (!t.measured) continue;
    for (size_t h = 0; h < t.heads.size(); ++h) {
      const HeadScore& s = t.heads[h];
      if (!std::isfinite(s.lift_mm)) continue;
      values.push_back({{"test", t.id},
                        {"head", plan.mechanism.heads[h].name},
                        {"lift_mm", s.lift_mm},
                        {"low_mm", s.lift_mm - 2.0 * s.u_lift_mm},
                        {"high_mm", s.lift_mm + 2.0 * s.u_lift_mm},
                        {"shift_mm", s.lift_shift_mm}});
    }
  }
  const json test_axis = {
      {"field", "test"}, {"type", "nominal"}, {"sort", nullptr}};
  const json tooltip = {{{"field", "test"}},
                        {{"field", "lift_mm"}, {"title", "lift [mm]"}},
                        {{"field", "high_mm"}, {"title", "lift + U [mm]"}},
                        {{"field", "shift_mm"},
                         {"title", "parallax shift of the displacement [mm]"}}};
  return {{"$schema", kVegaLiteSchema},
          {"title",
           "Lift toward the camera per test point (actuated - initial), with "
           "U = 2u"},
          {"data", {{"values", values}}},
          {"facet", {{"field", "head"}, {"type", "nominal"}}},
          {"spec",
           {{"width", 420},
            {"height", 180},
            {"layer",
             {{{"mark", "rule"},
               {"encoding",
                {{"x", test_axis},
                 {"y",
                  {{"field", "low_mm"},
                   {"type", "quantitative"},
                   {"title", "lift [mm]"}}},
                 {"y2", {{"field", "high_mm"}}},
                 {"tooltip", tooltip}}}},
              {{"mark", {{"type", "point"}, {"filled", true}}},
               {"encoding",
                {{"x", test_axis},
                 {"y", {{"field", "lift_mm"}, {"type", "quantitative"}}},
                 {"tooltip", tooltip}}}}}}}}};
}

namespace {

// A chart over the video's time: the windows shaded (`window_colour` and
// `window_tooltip` encode them) under lines of `values` (fields t, axis,
// segment, where lines break, and `field`).
json TimeChart(const std::string& title, const json& windows,
               const json& window_colour, const json& window_tooltip,
               const json& values, const std::string& field,
               const std::string& y_title, int height) {
  return {
      {"$schema", kVegaLiteSchema},
      {"title", title},
      {"width", 1000},
      {"height", height},
      {"layer",
       {{{"data", {{"values", windows}}},
         {"mark", {{"type", "rect"}, {"opacity", 0.25}}},
         {"encoding",
          {{"x", {{"field", "start"}, {"type", "quantitative"}}},
           {"x2", {{"field", "end"}}},
           {"color", window_colour},
           {"tooltip", window_tooltip}}}},
        {{"data", {{"values", values}}},
         {"mark", {{"type", "line"}, {"strokeWidth", 1}}},
         {"encoding",
          {{"x",
            {{"field", "t"}, {"type", "quantitative"}, {"title", "time [s]"}}},
           {"y",
            {{"field", field}, {"type", "quantitative"}, {"title", y_title}}},
           {"stroke", {{"field", "axis"}, {"type", "nominal"}}},
           {"detail", {{"field", "segment"}}}}}}}},
      {"resolve", {{"scale", {{"color", "independent"}}}}}};
}

}  // namespace

json TrajectoryChart(const TestPlan& plan, const VideoMeasurement& m,
                     const ValidationResult& r) {
  json values = json::array();
  // Lines break where frames were not read (windows-only mode).
  int segment = 0;
  for (size_t i = 0; i < m.frames.size(); ++i) {
    const FrameSample& f = m.frames[i];
    if (i > 0 && f.frame > m.frames[i - 1].frame + 1) ++segment;
    for (size_t h = 0; h < f.heads.size(); ++h) {
      const Eigen::Vector2d& d = f.heads[h].displacement_mm;
      if (!d.allFinite()) continue;
      const std::string head = plan.mechanism.heads[h].name;
      for (int axis = 0; axis < 2; ++axis) {
        values.push_back({{"t", f.time_s},
                          {"axis", head + (axis == 0 ? " y" : " z")},
                          {"mm", d[axis]},
                          {"segment", segment}});
      }
    }
  }
  json windows = json::array();
  for (const TestScore& t : r.tests) {
    for (int k = 0; k < 3; ++k) {
      windows.push_back({{"start", t.windows[k].start_s},
                         {"end", t.windows[k].end_s},
                         {"window", kWindowNames[k]},
                         {"test", t.id}});
    }
  }
  return TimeChart("Head displacements over time; windows shaded", windows,
                   {{"field", "window"},
                    {"type", "nominal"},
                    {"scale", {{"range", {"#4c78a8", "#f58518", "#54a24b"}}}}},
                   {{{"field", "test"}}, {{"field", "window"}}}, values, "mm",
                   "displacement [mm]", 260);
}

json CameraMotionChart(const VideoMeasurement& m, const ValidationResult& r) {
  json values = json::array();
  int segment = 0;
  for (size_t i = 0; i < m.frames.size(); ++i) {
    const FrameSample& f = m.frames[i];
    if (i > 0 && f.frame > m.frames[i - 1].frame + 1) ++segment;
    if (!f.registered) {
      ++segment;
      continue;
    }
    for (int axis = 0; axis < 2; ++axis) {
      values.push_back({{"t", f.time_s},
                        {"axis", axis == 0 ? "x (right)" : "y (down)"},
                        {"px", f.camera_shift_px[axis]},
                        {"segment", segment}});
    }
  }
  json windows = json::array();
  for (const TestScore& t : r.tests) {
    for (int k = 0; k < 3; ++k) {
      const WindowSummary& w = t.windows[k];
      windows.push_back({{"start", w.start_s},
                         {"end", w.end_s},
                         {"window", w.camera_moved ? "camera moved" : "window"},
                         {"test", t.id + " " + kWindowNames[k]},
                         {"motion_px", w.camera_motion_px}});
    }
  }
  return TimeChart(
      "Camera shift since the first frame [px] (" + m.registration +
          "); windows shaded",
      windows,
      {{"field", "window"},
       {"type", "nominal"},
       {"scale",
        {{"domain", {"window", "camera moved"}},
         {"range", {"#bab0ac", "#e45756"}}}}},
      {{{"field", "test"}}, {{"field", "motion_px"}, {"format", ".2f"}}},
      values, "px", "camera shift [px]", 200);
}

}  // namespace softbench
