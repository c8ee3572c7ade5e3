#include "pipelines/reports/validation_report.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>

#include "pipelines/measurement/snapshots.h"
#include "pipelines/reports/html_report.h"
#include "util/version.h"
#include "vision/image_data_uri.h"

namespace softbench {
namespace {

using nlohmann::json;

// Domains for y and z of the same length (the larger extent of the two, with
// a margin), each centred on its data: drawn in a square, equal axes.
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

// Fig. 4.8 / 4.16: measured and predicted displacements per test, with lines
// from each measurement to its predictions.
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
       "equal axes"},
      {"data", {{"values", values}}},
      {"facet", {{"field", "head"}, {"type", "nominal"}}},
      {"spec",
       {{"width", 380},
        {"height", 380},
        {"layer",
         {{{"transform", {{{"filter", "datum.series == 'error line'"}}}},
           {"mark", {{"type", "line"}, {"color", "#bbb"}, {"strokeWidth", 1}}},
           {"encoding", {{"x", x}, {"y", y}, {"detail", {{"field", "pair"}}}}}},
          {{"transform", {{{"filter", "datum.series != 'error line'"}}}},
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

// Fig. 4.9 / 4.17: error magnitude per test for both models.
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
    }
  }
  return {
      {"$schema", kVegaLiteSchema},
      {"title", "Position error per test point (figs. 4.9, 4.17)"},
      {"data", {{"values", values}}},
      {"facet", {{"field", "head"}, {"type", "nominal"}}},
      {"spec",
       {{"width", 420},
        {"height", 220},
        {"mark", "bar"},
        {"encoding",
         {{"x", {{"field", "test"}, {"type", "nominal"}, {"sort", nullptr}}},
          {"xOffset", {{"field", "model"}}},
          {"y",
           {{"field", "error"},
            {"type", "quantitative"},
            {"title", "|measured - predicted| [mm]"}}},
          {"color", {{"field", "model"}, {"type", "nominal"}}},
          {"tooltip",
           {{{"field", "test"}},
            {{"field", "model"}},
            {{"field", "error"}}}}}}}}};
}

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

// The trajectory of every head over time, with the windows shaded.
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

// The camera's shift since the reference frame over the whole video (the
// registration to the bench), with the windows shaded and those in which
// the camera moved named.
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

// A mark drawn over a crop, at a sub-pixel position in the frame.
struct CropMark {
  Eigen::Vector2d pixel;
  std::string colour;
  bool cross = false;  // a cross; otherwise a ring
  std::string label;   // tooltip
};

// One head's crop as SVG: the pixels (JPEG, drawn unsmoothed) in frame
// pixel coordinates, so the marks sit at their exact sub-pixel places.
std::string CropSvg(const HeadCrop& crop, const std::vector<CropMark>& marks,
                    double dot_radius_px) {
  // Pixel i covers [i - 0.5, i + 0.5] (OpenCV's centres are integers).
  const double x0 = crop.origin_px.x() - 0.5, y0 = crop.origin_px.y() - 0.5;
  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"{} {} {} {}\">"
      "<image href=\"{}\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" "
      "style=\"image-rendering:pixelated\"/>",
      x0, y0, crop.bgr.cols, crop.bgr.rows, JpegDataUri(crop.bgr, 92), x0, y0,
      crop.bgr.cols, crop.bgr.rows);
  const double r = 0.35 * dot_radius_px;
  for (const CropMark& mark : marks) {
    if (!mark.pixel.allFinite()) continue;
    const double x = mark.pixel.x(), y = mark.pixel.y();
    const std::string style = fmt::format(
        "stroke=\"{}\" stroke-width=\"1.5\" fill=\"none\" "
        "vector-effect=\"non-scaling-stroke\"",
        mark.colour);
    if (mark.cross) {
      svg += fmt::format(
          "<path d=\"M{} {}L{} {}M{} {}L{} {}\" {}><title>{}</title></path>",
          x - r, y - r, x + r, y + r, x - r, y + r, x + r, y - r, style,
          mark.label);
    } else {
      svg += fmt::format(
          R"(<circle cx="{}" cy="{}" r="{}" {}><title>{}</title></circle>)", x,
          y, r, style, mark.label);
    }
  }
  return svg + "</svg>";
}

// Annotated crops of every test's initial, actuated and final windows (the
// thesis's three frames), a row per test and head.
void AddCrops(const TestPlan& plan, const VideoMeasurement& m,
              const ValidationResult& r, HtmlReport* report) {
  std::map<double, const FrameSnapshot*> by_time;
  for (const FrameSnapshot& s : m.snapshots) by_time[s.requested_s] = &s;
  report->AddParagraph(
      "The frame in the middle of each window. Rings: the dots' sub-pixel "
      "centres (cyan) and the head centre in this frame (green); magenta "
      "cross: "
      "the initial position (initial window's median); on the actuated "
      "frame, the predicted positions: model blue, baseline orange. Hover a "
      "mark for its name.");
  for (const TestScore& t : r.tests) {
    for (size_t h = 0; h < t.heads.size(); ++h) {
      const HeadScore& score = t.heads[h];
      const Eigen::Vector2d initial_mm =
          m.rest_mm[h] + t.windows[0].median_mm[h];
      const auto pixel_of = [&](const Eigen::Vector2d& displacement_mm) {
        const Eigen::Vector2d plane = initial_mm + displacement_mm;
        return plane.allFinite() ? m.mapping->ToPixel(plane)
                                 : Eigen::Vector2d::Constant(NAN);
      };
      const double dot_radius_px =
          0.5 * plan.markers[h].dot_diameter_mm / m.mm_per_px;
      std::vector<HtmlReport::Figure> figures;
      for (int k = 0; k < 3; ++k) {
        const WindowSummary& w = t.windows[k];
        const auto it = by_time.find(w.middle_s());
        if (it == by_time.end() || it->second->heads[h].bgr.empty()) continue;
        const FrameSnapshot& snapshot = *it->second;
        const FrameSample* sample = FindFrame(m, snapshot.time_s);
        if (sample == nullptr) continue;
        const HeadObservation& obs = sample->heads[h].observation;
        std::vector<CropMark> marks;
        for (const DotObservation& dot : obs.dots) {
          if (dot.found) marks.push_back({dot.pixel, "#0ff", false, "dot"});
        }
        marks.push_back({obs.pixel, "#0f0", false, "head centre"});
        marks.push_back({pixel_of(Eigen::Vector2d::Zero()), "#f0f", true,
                         "initial position"});
        if (k == 1) {
          marks.push_back(
              {pixel_of(score.model_mm), "#4c9bff", true, r.model_name});
          marks.push_back(
              {pixel_of(score.baseline_mm), "#ff9a3c", true, r.baseline_name});
        }
        figures.push_back(
            {CropSvg(snapshot.heads[h], marks, dot_radius_px),
             fmt::format("{} {}, {}: frame {} (t = {:.2f} s)", t.id,
                         plan.mechanism.heads[h].name, kWindowNames[k],
                         snapshot.frame, snapshot.time_s)});
      }
      if (!figures.empty()) report->AddFigures(figures);
    }
  }
}

}  // namespace

std::string FormatMm(double value) {
  return std::isfinite(value) ? fmt::format("{:.4f}", value) : "";
}

namespace {

// The error statistics of the model and the baseline, per head.
void AddSummary(const TestPlan& plan, const ValidationResult& r,
                HtmlReport* report) {
  report->AddHeading("Summary");
  std::vector<std::vector<std::string>> rows;
  for (int h = 0; h < plan.mechanism.NumHeads(); ++h) {
    const ErrorStatistics& a = r.model_errors[h];
    const ErrorStatistics& b = r.baseline_errors[h];
    std::vector<double> uncertainties;
    for (const TestScore& t : r.tests) {
      if (t.scored()) uncertainties.push_back(t.heads[h].uncertainty_mm);
    }
    rows.push_back({plan.mechanism.heads[h].name, std::to_string(a.tests),
                    FormatMm(a.mean_mm), FormatMm(a.max_mm), FormatMm(a.rms_mm),
                    FormatMm(b.mean_mm), FormatMm(b.max_mm), FormatMm(b.rms_mm),
                    fmt::format("{:.0f} %", r.improvement_percent[h]),
                    uncertainties.empty()
                        ? std::string()
                        : FormatMm(*std::max_element(uncertainties.begin(),
                                                     uncertainties.end()))});
  }
  report->AddTable({"head", "tests", "model mean [mm]", "model max",
                    "model RMS", "baseline mean", "baseline max",
                    "baseline RMS", "improvement", "largest uncertainty [mm]"},
                   rows);
  report->AddParagraph(
      "Uncertainty: the standard uncertainty of a measured displacement from "
      "its windows' own scatter (each window median's standard error, "
      "1.2533 x spread / sqrt(frames), initial and actuated in quadrature). "
      "It is a floor: frames within a window share slow errors.");
}

// "p1 p2 p3" as the plan gives them.
std::string Pressures(const Eigen::VectorXd& pressures) {
  std::vector<std::string> values;
  for (double p : pressures) values.push_back(fmt::format("{:g}", p));
  return fmt::format("{}", fmt::join(values, "  "));
}

void AddTestTable(const TestPlan& plan, const ValidationResult& r,
                  HtmlReport* report) {
  report->AddHeading("Test points");
  std::vector<std::vector<std::string>> rows;
  for (const TestScore& t : r.tests) {
    for (size_t h = 0; h < t.heads.size(); ++h) {
      const HeadScore& s = t.heads[h];
      std::vector<std::string> frames;
      for (const WindowSummary& w : t.windows) {
        frames.push_back(h < w.head_frames.size()
                             ? std::to_string(w.head_frames[h])
                             : std::string("-"));
      }
      rows.push_back({t.id, Pressures(t.pressures),
                      plan.mechanism.heads[h].name, FormatMm(s.measured_mm.x()),
                      FormatMm(s.measured_mm.y()), FormatMm(s.uncertainty_mm),
                      fmt::format("{}", fmt::join(frames, " / ")),
                      FormatMm(s.model_error_mm), FormatMm(s.baseline_error_mm),
                      FormatMm(s.hysteresis_mm),
                      t.status + (t.reason.empty() ? "" : ": " + t.reason)});
    }
  }
  for (const TestPoint& t : plan.skipped_tests) {
    rows.push_back({t.id, Pressures(t.pressures), "", "", "", "", "", "", "",
                    "", "skipped (as the plan says)"});
  }
  report->AddTable({"test", "pressures [" + plan.pressure_unit + "]", "head",
                    "measured dy [mm]", "measured dz [mm]", "uncertainty [mm]",
                    "frames initial / actuated / final", "model error [mm]",
                    "baseline error [mm]", "hysteresis [mm]", "status"},
                   rows);
}

void AddRepeats(const TestPlan& plan, const ValidationResult& r,
                HtmlReport* report) {
  report->AddHeading("Repeats");
  std::vector<std::vector<std::string>> rows;
  for (const RepeatAgreement& group : r.repeats) {
    std::vector<std::string> row = {
        fmt::format("{}", fmt::join(group.test_ids, ", "))};
    for (double d : group.max_difference_mm) row.push_back(FormatMm(d));
    rows.push_back(row);
  }
  std::vector<std::string> header = {"tests with the same pressures"};
  for (const Head& head : plan.mechanism.heads) {
    header.push_back(head.name + ": largest difference [mm]");
  }
  report->AddTable(header, rows);
}

// How pixels became millimetres, and how the frames went.
void AddCalibration(const TestPlan& plan, const VideoMeasurement& m,
                    HtmlReport* report) {
  report->AddHeading("Calibration");
  report->AddTable(
      {"item", "value"},
      {{"scale", m.scale_source},
       {"tag", plan.calibration.tag
                   ? fmt::format("{} id {}, {} mm; dots {} mm above it",
                                 plan.calibration.tag->family,
                                 plan.calibration.tag->id,
                                 plan.calibration.tag->size_mm,
                                 plan.calibration.plane_offset_mm)
                   : std::string("none")},
       {"camera tilt to the dot plane (corrected)",
        fmt::format("{:.2f} deg",
                    m.mapping->TiltRad() * 180.0 / std::numbers::pi)},
       {"lens", plan.calibration.intrinsics_path.empty()
                    ? fmt::format("pinhole, {} mm equivalent focal length",
                                  plan.calibration.focal_length_35mm)
                    : "intrinsics " + plan.calibration.intrinsics_path},
       {"mm per pixel at the image centre", fmt::format("{:.5f}", m.mm_per_px)},
       {"distortion check", m.distortion.message},
       {"registration to the bench", m.registration},
       {"frames not registered",
        m.unregistered_frames == 0
            ? std::string("0")
            : fmt::format("{} ({}: {})", m.unregistered_frames,
                          UnregisteredSpans(m.frames), m.unregistered_reason)},
       {"frames", std::to_string(m.frames.size())},
       {"dot-frames missing", std::to_string(m.missing_dots)},
       {"frames searched in full", std::to_string(m.full_frame_frames)},
       {"same-colour blobs rejected", std::to_string(m.rejected_blobs)}});
}

// What the report was made from: softbench's version and every input file
// with its SHA-256.
void AddInputs(const VideoValidation& v, HtmlReport* report) {
  report->AddHeading("Inputs");
  report->AddParagraph(fmt::format("softbench {}; pressures in {}.",
                                   SoftbenchVersion(), v.plan.pressure_unit));
  std::vector<std::vector<std::string>> rows;
  for (const InputFile& file : v.inputs) {
    rows.push_back({file.role, file.path, file.sha256});
  }
  report->AddTable({"input", "file", "SHA-256"}, rows);
}

}  // namespace

std::string ValidationReportHtml(const VideoValidation& v) {
  const TestPlan& plan = v.plan;
  const VideoMeasurement& m = v.measurement;
  const ValidationResult& r = v.result;
  HtmlReport report("Validation: " + m.video_path);
  report.AddLinks("Files beside this page:",
                  {std::begin(kValidationFiles), std::end(kValidationFiles)});
  report.AddParagraph(fmt::format(
      "{} mechanism, plan {}, {} test points (times from {}); model {} "
      "against the baseline {}.",
      plan.mechanism.name, plan.path, r.tests.size(), r.times_source,
      r.model_name, r.baseline_name));
  for (const std::string& warning : r.warnings) {
    report.AddParagraph("Warning: " + warning);
  }
  AddSummary(plan, r, &report);
  report.AddChart(PositionChart(plan, r));
  report.AddChart(ErrorChart(plan, r));
  report.AddChart(TrajectoryChart(plan, m, r));
  if (m.registers_frames) report.AddChart(CameraMotionChart(m, r));
  report.AddHeading("Frames");
  AddCrops(plan, m, r, &report);
  AddTestTable(plan, r, &report);
  report.AddHeading("Hysteresis");
  report.AddParagraph(fmt::format(
      "Tolerance {} mm; flagged: {}. {}", plan.hysteresis_tolerance_mm,
      r.hysteresis_flagged.empty()
          ? std::string("none")
          : fmt::format("{}", fmt::join(r.hysteresis_flagged, ", ")),
      r.hysteresis_cause));
  AddRepeats(plan, r, &report);
  AddCalibration(plan, m, &report);
  AddInputs(v, &report);
  return report.Render();
}

}  // namespace softbench
