#include "pipelines/validate_command.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numbers>

#include "pipelines/html_report.h"
#include "pipelines/model_selection.h"
#include "pipelines/pressure_csv.h"
#include "pipelines/pressure_log.h"
#include "pipelines/test_point_detection.h"
#include "pipelines/validation_report.h"
#include "util/atomic_file.h"
#include "util/input_error.h"
#include "util/parallel_tasks.h"
#include "util/progress.h"
#include "vision/video_reader.h"

namespace softbench {
namespace {

using nlohmann::json;

json SummaryJson(const TestPlan& plan, const VideoMeasurement& m,
                 const ValidationResult& r) {
  json root;
  root["video"] = m.video_path;
  root["plan"] = plan.path;
  root["mechanism"] = plan.mechanism.name;
  root["model"] = r.model_name;
  root["times_source"] = r.times_source;
  root["baseline"] = r.baseline_name;
  root["calibration"] = {
      {"scale_source", m.scale_source},
      {"mm_per_px", m.mm_per_px},
      {"tilt_deg", m.mapping->TiltRad() * 180.0 / std::numbers::pi},
      {"distortion_check", m.distortion.message},
      {"distortion_warning", m.distortion.warn}};
  root["registration"] = {{"method", m.registration},
                          {"unregistered_frames", m.unregistered_frames},
                          {"first_reason", m.unregistered_reason},
                          {"camera_moved_windows", r.camera_moved_windows}};
  root["frames"] = m.frames.size();
  root["every_frame"] = m.every_frame;
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
      json window = {{"start_s", w.start_s},
                     {"end_s", w.end_s},
                     {"frames", w.frames},
                     {"unregistered_frames", w.unregistered_frames},
                     {"camera_shift_px",
                      {JsonNumber(w.camera_shift_px.x()),
                       JsonNumber(w.camera_shift_px.y())}},
                     {"camera_motion_px", w.camera_motion_px}};
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
  c->add_flag("--no-registration", options->no_registration,
              "take the camera to be still instead of registering every "
              "frame to the bench (the thesis's method)");
  c->add_flag("--windows-only", options->windows_only,
              "read only the frames of the tests' windows, seeking between "
              "them (needs the times in the plan)");
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
        csv += "," + FormatMm(t.windows[k].median_mm[h].x()) + "," +
               FormatMm(t.windows[k].median_mm[h].y());
      }
      for (const Eigen::Vector2d& v : {s.measured_mm, s.model_mm}) {
        csv += "," + FormatMm(v.x()) + "," + FormatMm(v.y());
      }
      csv += "," + FormatMm(s.model_error_mm) + "," +
             FormatMm(s.baseline_mm.x()) + "," + FormatMm(s.baseline_mm.y()) +
             "," + FormatMm(s.baseline_error_mm) + "," +
             FormatMm(s.hysteresis_mm) + "," +
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
  measure.register_frames = !options.no_registration;
  const bool times_known = plan.HasTimes() && holds.empty();
  measure.rest_s = times_known ? *plan.tests.front().actuate_s : options.rest_s;
  if (times_known) {
    // The windows are known before measuring: their frames' crops are kept
    // on the way, and in windows-only mode they are all that is read.
    VideoReaderOptions probe;
    probe.want_luma = probe.want_bgr = false;
    const auto windows =
        PlanWindows(plan, VideoReader(video_path, probe).info().LastFrameS());
    measure.snapshot_times_s = WindowMiddles(windows);
    for (const auto& test : windows) {
      for (const WindowSummary& w : test) {
        if (options.windows_only) measure.spans.push_back({w.start_s, w.end_s});
      }
    }
  } else if (options.windows_only) {
    throw InputError(fmt::format(
        "{}: --windows-only needs the test times before reading the video; "
        "give every test actuate_s and release_s in the plan (times from the "
        "motion or a pressure log need every frame)",
        plan.path));
  }
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
  if (!times_known) {
    // The plan has its times now.
    CaptureSnapshots(plan, WindowMiddles(PlanWindows(plan, m.last_frame_s)),
                     &m);
  }
  return {std::move(plan), std::move(m), std::move(result)};
}

// The four report files of one video into `directory`.
void WriteValidationFiles(const VideoValidation& v,
                          const std::filesystem::path& directory) {
  std::filesystem::create_directories(directory);
  WriteFileAtomically((directory / "report.html").string(),
                      ValidationReportHtml(v.plan, v.measurement, v.result));
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
                      FormatMm(r.model_errors[h].mean_mm),
                      FormatMm(r.model_errors[h].max_mm),
                      FormatMm(r.baseline_errors[h].mean_mm),
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
