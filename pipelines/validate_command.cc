#include "pipelines/validate_command.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "pipelines/html_report.h"
#include "pipelines/model_selection.h"
#include "pipelines/pressure_csv.h"
#include "pipelines/pressure_log.h"
#include "pipelines/test_point_detection.h"
#include "util/atomic_file.h"
#include "util/input_error.h"
#include "util/parallel_tasks.h"
#include "util/progress.h"

namespace softbench {
namespace {

using nlohmann::json;

std::string Mm(double value) {
  return std::isfinite(value) ? fmt::format("{:.4f}", value) : "";
}

json SummaryJson(const TestPlan& plan, const VideoMeasurement& m,
                 const ValidationResult& r) {
  json root;
  root["video"] = m.video_path;
  root["plan"] = plan.path;
  root["mechanism"] = plan.mechanism.name;
  root["model"] = r.model_name;
  root["times_source"] = r.times_source;
  root["baseline"] = r.baseline_name;
  root["calibration"] = {{"scale_source", m.scale_source},
                         {"mm_per_px", m.mm_per_px},
                         {"distortion_check", m.distortion.message},
                         {"distortion_warning", m.distortion.warn}};
  root["frames"] = m.frames.size();
  root["missing_dots"] = m.missing_dots;
  root["full_frame_frames"] = m.full_frame_frames;
  for (int h = 0; h < plan.mechanism.NumHeads(); ++h) {
    const auto stats = [](const ErrorStatistics& s) {
      return json{{"tests", s.tests},
                  {"mean_mm", JsonNumber(s.mean_mm)},
                  {"max_mm", JsonNumber(s.max_mm)},
                  {"rms_mm", JsonNumber(s.rms_mm)}};
    };
    root["heads"].push_back(
        {{"head", plan.mechanism.heads[h].name},
         {"model_error", stats(r.model_errors[h])},
         {"baseline_error", stats(r.baseline_errors[h])},
         {"improvement_percent", JsonNumber(r.improvement_percent[h])}});
  }
  for (const RepeatAgreement& group : r.repeats) {
    root["repeats"].push_back({{"tests", group.test_ids},
                               {"max_difference_mm", group.max_difference_mm}});
  }
  root["hysteresis"] = {{"tolerance_mm", plan.hysteresis_tolerance_mm},
                        {"flagged", r.hysteresis_flagged},
                        {"shared_cause", r.hysteresis_cause}};
  root["warnings"] = r.warnings;
  for (const TestScore& t : r.tests) {
    json test = {{"id", t.id}, {"status", t.status}, {"reason", t.reason}};
    for (int k = 0; k < 3; ++k) {
      const WindowSummary& w = t.windows[k];
      json window = {
          {"start_s", w.start_s}, {"end_s", w.end_s}, {"frames", w.frames}};
      for (size_t h = 0; h < w.median_mm.size(); ++h) {
        window["heads"].push_back(
            {{"frames", w.head_frames[h]},
             {"median_mm",
              {JsonNumber(w.median_mm[h].x()), JsonNumber(w.median_mm[h].y())}},
             {"spread_mm",
              {JsonNumber(w.spread_mm[h].x()),
               JsonNumber(w.spread_mm[h].y())}}});
      }
      test["windows"][kWindowNames[k]] = window;
    }
    root["tests"].push_back(test);
  }
  return root;
}

// Fig. 4.8 / 4.16: measured and predicted displacements per test, with lines
// from each measurement to its predictions.
json PositionChart(const TestPlan& plan, const ValidationResult& r) {
  json values = json::array();
  for (const TestScore& t : r.tests) {
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
  const json x = {
      {"field", "y"}, {"type", "quantitative"}, {"title", "y [mm]"}};
  const json y = {
      {"field", "z"}, {"type", "quantitative"}, {"title", "z [mm]"}};
  return {
      {"$schema", "https://vega.github.io/schema/vega-lite/v6.json"},
      {"title", "Measured and predicted displacements (figs. 4.8, 4.16)"},
      {"data", {{"values", values}}},
      {"facet", {{"field", "head"}, {"type", "nominal"}}},
      {"spec",
       {{"width", 420},
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
      {"$schema", "https://vega.github.io/schema/vega-lite/v6.json"},
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

// The trajectory of every head over time, with the windows shaded.
json TrajectoryChart(const TestPlan& plan, const VideoMeasurement& m,
                     const ValidationResult& r) {
  json values = json::array();
  for (const FrameSample& f : m.frames) {
    for (size_t h = 0; h < f.heads.size(); ++h) {
      const Eigen::Vector2d& d = f.heads[h].displacement_mm;
      if (!d.allFinite()) continue;
      const std::string head = plan.mechanism.heads[h].name;
      values.push_back({{"t", f.time_s}, {"axis", head + " y"}, {"mm", d.x()}});
      values.push_back({{"t", f.time_s}, {"axis", head + " z"}, {"mm", d.y()}});
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
  return {
      {"$schema", "https://vega.github.io/schema/vega-lite/v6.json"},
      {"title", "Head displacements over time; windows shaded"},
      {"width", 1000},
      {"height", 260},
      {"layer",
       {{{"data", {{"values", windows}}},
         {"mark", {{"type", "rect"}, {"opacity", 0.25}}},
         {"encoding",
          {{"x", {{"field", "start"}, {"type", "quantitative"}}},
           {"x2", {{"field", "end"}}},
           {"color",
            {{"field", "window"},
             {"type", "nominal"},
             {"scale", {{"range", {"#4c78a8", "#f58518", "#54a24b"}}}}}},
           {"tooltip", {{{"field", "test"}}, {{"field", "window"}}}}}}},
        {{"data", {{"values", values}}},
         {"mark", {{"type", "line"}, {"strokeWidth", 1}}},
         {"encoding",
          {{"x",
            {{"field", "t"}, {"type", "quantitative"}, {"title", "time [s]"}}},
           {"y",
            {{"field", "mm"},
             {"type", "quantitative"},
             {"title", "displacement [mm]"}}},
           {"stroke", {{"field", "axis"}, {"type", "nominal"}}}}}}}},
      {"resolve", {{"scale", {{"color", "independent"}}}}}};
}

std::string ReportHtml(const TestPlan& plan, const VideoMeasurement& m,
                       const ValidationResult& r) {
  HtmlReport report("Validation: " + m.video_path);
  report.AddParagraph(fmt::format(
      "{} mechanism, plan {}, {} test points (times from {}); model {} "
      "against the baseline {}.",
      plan.mechanism.name, plan.path, r.tests.size(), r.times_source,
      r.model_name, r.baseline_name));
  for (const std::string& warning : r.warnings) {
    report.AddParagraph("Warning: " + warning);
  }
  report.AddHeading("Summary");
  std::vector<std::vector<std::string>> rows;
  for (int h = 0; h < plan.mechanism.NumHeads(); ++h) {
    const ErrorStatistics& a = r.model_errors[h];
    const ErrorStatistics& b = r.baseline_errors[h];
    rows.push_back({plan.mechanism.heads[h].name, std::to_string(a.tests),
                    Mm(a.mean_mm), Mm(a.max_mm), Mm(a.rms_mm), Mm(b.mean_mm),
                    Mm(b.max_mm), Mm(b.rms_mm),
                    fmt::format("{:.0f} %", r.improvement_percent[h])});
  }
  report.AddTable(
      {"head", "tests", "model mean [mm]", "model max", "model RMS",
       "baseline mean", "baseline max", "baseline RMS", "improvement"},
      rows);
  report.AddChart(PositionChart(plan, r));
  report.AddChart(ErrorChart(plan, r));
  report.AddChart(TrajectoryChart(plan, m, r));
  report.AddHeading("Test points");
  rows.clear();
  for (const TestScore& t : r.tests) {
    for (size_t h = 0; h < t.heads.size(); ++h) {
      const HeadScore& s = t.heads[h];
      rows.push_back({t.id, plan.mechanism.heads[h].name, Mm(s.measured_mm.x()),
                      Mm(s.measured_mm.y()), Mm(s.model_error_mm),
                      Mm(s.baseline_error_mm), Mm(s.hysteresis_mm),
                      t.status + (t.reason.empty() ? "" : ": " + t.reason)});
    }
  }
  report.AddTable(
      {"test", "head", "measured dy [mm]", "measured dz [mm]",
       "model error [mm]", "baseline error [mm]", "hysteresis [mm]", "status"},
      rows);
  report.AddHeading("Hysteresis");
  report.AddParagraph(fmt::format(
      "Tolerance {} mm; flagged: {}. {}", plan.hysteresis_tolerance_mm,
      r.hysteresis_flagged.empty()
          ? std::string("none")
          : fmt::format("{}", fmt::join(r.hysteresis_flagged, ", ")),
      r.hysteresis_cause));
  report.AddHeading("Repeats");
  rows.clear();
  for (const RepeatAgreement& group : r.repeats) {
    std::vector<std::string> row = {
        fmt::format("{}", fmt::join(group.test_ids, ", "))};
    for (double d : group.max_difference_mm) row.push_back(Mm(d));
    rows.push_back(row);
  }
  std::vector<std::string> header = {"tests with the same pressures"};
  for (const Head& head : plan.mechanism.heads) {
    header.push_back(head.name + ": largest difference [mm]");
  }
  report.AddTable(header, rows);
  report.AddHeading("Calibration");
  report.AddTable(
      {"item", "value"},
      {{"scale", m.scale_source},
       {"mm per pixel at the image centre", fmt::format("{:.5f}", m.mm_per_px)},
       {"distortion check", m.distortion.message},
       {"frames", std::to_string(m.frames.size())},
       {"dot-frames missing", std::to_string(m.missing_dots)},
       {"frames searched in full", std::to_string(m.full_frame_frames)},
       {"same-colour blobs rejected", std::to_string(m.rejected_blobs)}});
  return report.Render();
}

}  // namespace

void AddValidateCommand(CLI::App* app, ValidateCommandOptions* options) {
  CLI::App* c = app->add_subcommand(
      "validate", "Bench video and test plan to a model-validation report");
  c->add_option("videos", options->video_paths,
                "bench video(s); several get one report each and an index")
      ->required();
  c->add_option("--jobs", options->jobs,
                "videos measured at once (0: one per core)")
      ->capture_default_str();
  c->add_option("--plan", options->plan_path, "test plan YAML")->required();
  c->add_option("--out", options->output_directory, "report directory")
      ->required();
  c->add_option("--constants", options->constants_path,
                "actuator constants (default: the plan's)");
  c->add_option("--pressure-log", options->pressure_log_path,
                "the regulator's log (time_s,p1..pN): test times from it, "
                "its clock aligned by the motion");
  c->add_option("--rest-s", options->rest_s,
                "plan without times: seconds at rest at the video's start")
      ->capture_default_str();
  c->add_option("--variant", options->variant,
                "small-angle, full-trig or variable-arm (default: the plan's)");
}

std::string ResultsCsv(const TestPlan& plan, const ValidationResult& r) {
  std::string csv = "test_id,head";
  for (int k = 1; k <= plan.mechanism.NumActuators(); ++k) {
    csv += fmt::format(",p{}", k);
  }
  csv +=
      ",initial_y_mm,initial_z_mm,actuated_y_mm,actuated_z_mm,final_y_mm,"
      "final_z_mm,measured_dy_mm,measured_dz_mm,model_dy_mm,model_dz_mm,"
      "model_error_mm,baseline_dy_mm,baseline_dz_mm,baseline_error_mm,"
      "hysteresis_mm,hysteresis_ok,status\n";
  for (const TestScore& t : r.tests) {
    for (size_t h = 0; h < t.heads.size(); ++h) {
      const HeadScore& s = t.heads[h];
      csv += t.id + "," + plan.mechanism.heads[h].name;
      for (int k = 0; k < t.pressures.size(); ++k) {
        csv += fmt::format(",{:g}", t.pressures[k]);
      }
      for (int k = 0; k < 3; ++k) {
        csv += "," + Mm(t.windows[k].median_mm[h].x()) + "," +
               Mm(t.windows[k].median_mm[h].y());
      }
      for (const Eigen::Vector2d& v : {s.measured_mm, s.model_mm}) {
        csv += "," + Mm(v.x()) + "," + Mm(v.y());
      }
      csv += "," + Mm(s.model_error_mm) + "," + Mm(s.baseline_mm.x()) + "," +
             Mm(s.baseline_mm.y()) + "," + Mm(s.baseline_error_mm) + "," +
             Mm(s.hysteresis_mm) + "," +
             (t.measured ? (s.hysteresis_ok ? "1" : "0") : "") + "," +
             t.status + "\n";
    }
  }
  return csv;
}

namespace {

// One video's measurement and scores, with the plan's times as used.
struct VideoValidation {
  TestPlan plan;
  VideoMeasurement measurement;
  ValidationResult result;
};

// The plan (with the options' model) and the pressure log's holds, checked
// against each other before any video work.
TestPlan LoadValidationPlan(const ValidateCommandOptions& options,
                            std::vector<PressureHold>* holds) {
  TestPlan plan = LoadTestPlan(options.plan_path);
  if (!options.constants_path.empty() || !options.variant.empty()) {
    plan.force_model = ResolveAxialShearModel(
        options.constants_path.empty() ? plan.constants_path
                                       : options.constants_path,
        options.variant.empty() ? std::string(VariantName(plan.force_model))
                                : options.variant,
        nullptr);
  }
  if (options.pressure_log_path.empty()) return plan;
  std::vector<double> times_s;
  const std::vector<Eigen::VectorXd> rows = ReadPressureRows(
      options.pressure_log_path, plan.mechanism.NumActuators(), &times_s);
  *holds = PressureLogHolds(times_s, rows, 1e-6);
  if (holds->size() != plan.tests.size()) {
    throw InputError(fmt::format(
        "{}: the log holds {} sets of pressures but the plan lists {} "
        "tests; give the plan one test per hold, in order",
        options.pressure_log_path, holds->size(), plan.tests.size()));
  }
  for (size_t i = 0; i < holds->size(); ++i) {
    const PressureHold& hold = (*holds)[i];
    if ((hold.pressures - plan.tests[i].pressures).cwiseAbs().maxCoeff() >
        1e-6) {
      throw InputError(fmt::format(
          "{}: hold {} (from t = {} s) is ({}) but plan test '{}' is ({}); "
          "the plan's tests must follow the log's order",
          options.pressure_log_path, i + 1, hold.start_s,
          fmt::join(hold.pressures, ", "), plan.tests[i].id,
          fmt::join(plan.tests[i].pressures, ", ")));
    }
  }
  return plan;
}

// Measures one video, finds its test points' times (plan, motion or log)
// and scores them.
VideoValidation ValidateVideo(TestPlan plan,
                              const std::vector<PressureHold>& holds,
                              const std::string& video_path,
                              const ValidateCommandOptions& options,
                              bool progress) {
  VideoMeasurementOptions measure;
  measure.progress = progress;
  measure.rest_s = plan.HasTimes() && holds.empty()
                       ? *plan.tests.front().actuate_s
                       : options.rest_s;
  VideoMeasurement m = MeasureVideo(plan, video_path, measure);
  std::string times_source = "the plan";
  if (!plan.HasTimes() || !holds.empty()) {
    const TestPointDetection detection = DetectTestPoints(
        m, static_cast<int>(plan.tests.size()), options.detection);
    if (!detection.found) {
      throw InputError(video_path + ": " + detection.why_not);
    }
    if (holds.empty()) {
      for (size_t i = 0; i < plan.tests.size(); ++i) {
        plan.tests[i].actuate_s = detection.points[i].actuate_s;
        plan.tests[i].release_s = detection.points[i].release_s;
      }
      times_source = fmt::format("the motion (heads beyond {:.3f} mm)",
                                 detection.threshold_mm);
    } else {
      const PressureLogAlignment alignment = AlignPressureLog(holds, detection);
      for (size_t i = 0; i < plan.tests.size(); ++i) {
        plan.tests[i].actuate_s = holds[i].start_s + alignment.offset_s;
        plan.tests[i].release_s = holds[i].end_s + alignment.offset_s;
      }
      times_source = fmt::format(
          "the pressure log {}, its clock {:+.3f} s from the video's (steps "
          "in the motion within {:.3f} s of it)",
          options.pressure_log_path, alignment.offset_s, alignment.spread_s);
    }
  }
  ValidationResult result = ScoreTests(plan, m, options.validation);
  result.times_source = times_source;
  return {std::move(plan), std::move(m), std::move(result)};
}

// The four report files of one video into `directory`.
void WriteValidationFiles(const VideoValidation& v,
                          const std::filesystem::path& directory) {
  std::filesystem::create_directories(directory);
  WriteFileAtomically((directory / "report.html").string(),
                      ReportHtml(v.plan, v.measurement, v.result));
  WriteFileAtomically((directory / "results.csv").string(),
                      ResultsCsv(v.plan, v.result));
  WriteFileAtomically(
      (directory / "summary.json").string(),
      SummaryJson(v.plan, v.measurement, v.result).dump(2) + "\n");
  WriteFileAtomically((directory / "trajectory.csv").string(),
                      TrajectoryCsv(v.plan, v.measurement));
}

// What the command prints of one video.
std::string SummaryText(const VideoValidation& v) {
  const ValidationResult& r = v.result;
  std::string text =
      fmt::format("{}: {} test points (times from {}), {} measured\n",
                  v.measurement.video_path, r.tests.size(), r.times_source,
                  std::count_if(r.tests.begin(), r.tests.end(),
                                [](const TestScore& t) { return t.measured; }));
  for (int h = 0; h < v.plan.mechanism.NumHeads(); ++h) {
    text += fmt::format(
        "  {}: model error mean {:.4f} mm (max {:.4f}), baseline {:.4f} mm "
        "(max {:.4f}): {:.0f} % better\n",
        v.plan.mechanism.heads[h].name, r.model_errors[h].mean_mm,
        r.model_errors[h].max_mm, r.baseline_errors[h].mean_mm,
        r.baseline_errors[h].max_mm, r.improvement_percent[h]);
  }
  text += fmt::format(
      "  hysteresis above {} mm: {} ({})\n", v.plan.hysteresis_tolerance_mm,
      r.hysteresis_flagged.empty()
          ? std::string("none")
          : fmt::format("{}", fmt::join(r.hysteresis_flagged, ", ")),
      r.hysteresis_cause);
  return text;
}

// index.html and index.csv of several videos' reports.
void WriteIndex(const std::vector<VideoValidation>& videos,
                const std::vector<std::string>& names,
                const AtomicDirectory& report) {
  HtmlReport index("Validation of " + std::to_string(videos.size()) +
                   " videos");
  std::string csv =
      "video,report,head,tests_measured,model_mean_mm,model_max_mm,"
      "baseline_mean_mm,improvement_percent,hysteresis_flagged\n";
  std::vector<std::vector<std::string>> rows;
  for (size_t i = 0; i < videos.size(); ++i) {
    const VideoValidation& v = videos[i];
    const ValidationResult& r = v.result;
    index.AddLink(v.measurement.video_path, names[i] + "/report.html");
    for (int h = 0; h < v.plan.mechanism.NumHeads(); ++h) {
      const std::string flagged =
          fmt::format("{}", fmt::join(r.hysteresis_flagged, " "));
      csv += fmt::format(
          "{},{}/report.html,{},{},{:.5f},{:.5f},{:.5f},{:.1f},{}\n",
          v.measurement.video_path, names[i], v.plan.mechanism.heads[h].name,
          r.model_errors[h].tests, r.model_errors[h].mean_mm,
          r.model_errors[h].max_mm, r.baseline_errors[h].mean_mm,
          r.improvement_percent[h], flagged);
      rows.push_back({names[i], v.plan.mechanism.heads[h].name,
                      std::to_string(r.model_errors[h].tests),
                      Mm(r.model_errors[h].mean_mm),
                      Mm(r.model_errors[h].max_mm),
                      Mm(r.baseline_errors[h].mean_mm),
                      fmt::format("{:.0f} %", r.improvement_percent[h]),
                      flagged.empty() ? "none" : flagged});
    }
  }
  index.AddTable({"video", "head", "tests", "model mean [mm]", "model max",
                  "baseline mean", "improvement", "hysteresis flagged"},
                 rows);
  WriteFileAtomically(report.File("index.html"), index.Render());
  WriteFileAtomically(report.File("index.csv"), csv);
}

}  // namespace

int RunValidate(const ValidateCommandOptions& options, std::ostream& out) {
  if (const std::optional<std::string> problem = options.validation.Check()) {
    throw InputError("validate: " + *problem);
  }
  if (options.video_paths.empty()) throw InputError("validate: give a video");
  if (options.jobs < 0) throw InputError("--jobs: must be >= 0");
  std::vector<PressureHold> holds;
  const TestPlan plan = LoadValidationPlan(options, &holds);
  const int count = static_cast<int>(options.video_paths.size());
  std::vector<VideoValidation> videos(count);
  if (count == 1) {
    videos[0] = ValidateVideo(plan, holds, options.video_paths[0], options,
                              !options.quiet);
  } else {
    // Videos in parallel; one bar for all of them.
    std::atomic<int> done{0};
    ProgressBar progress("videos", count, !options.quiet);
    RunParallelTasks(
        count, options.jobs,
        [&](int i) {
          videos[i] = ValidateVideo(plan, holds, options.video_paths[i],
                                    options, false);
          ++done;
        },
        [&] { progress.Update(done); });
    progress.Finish();
  }

  AtomicDirectory report(options.output_directory);
  if (count == 1) {
    WriteValidationFiles(videos[0], report.File(""));
  } else {
    // One folder per video, named after the file (made unique).
    std::vector<std::string> names;
    for (const std::string& path : options.video_paths) {
      std::string name = std::filesystem::path(path).stem().string();
      const std::string base = name;
      for (int k = 2;
           std::find(names.begin(), names.end(), name) != names.end(); ++k) {
        name = base + "_" + std::to_string(k);
      }
      names.push_back(name);
    }
    for (int i = 0; i < count; ++i) {
      WriteValidationFiles(videos[i], report.File(names[i]));
    }
    WriteIndex(videos, names, report);
  }
  report.Commit();

  for (const VideoValidation& v : videos) {
    for (const std::string& warning : v.result.warnings) {
      spdlog::warn("{}: {}", v.measurement.video_path, warning);
    }
    if (v.measurement.distortion.warn) {
      spdlog::warn("{}", v.measurement.distortion.message);
    }
    out << SummaryText(v);
  }
  out << fmt::format("report: {}/{}\n", options.output_directory,
                     count == 1 ? "report.html" : "index.html");
  return 0;
}

}  // namespace softbench
