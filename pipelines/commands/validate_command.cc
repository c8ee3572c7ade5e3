#include "pipelines/commands/validate_command.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <filesystem>

#include "model/actuator_model.h"
#include "pipelines/commands/common_flags.h"
#include "pipelines/commands/model_selection.h"
#include "pipelines/reports/validation_files.h"
#include "util/atomic_file.h"
#include "util/input_error.h"
#include "util/parallel_tasks.h"
#include "util/progress.h"

namespace softbench {
namespace {

// The plan (with the options' model) and the pressure log's holds, checked
// against each other before any video work.
TestPlan LoadValidationPlan(const ValidateCommandOptions& options,
                            std::optional<PressureLogTimes>* log) {
  TestPlan plan = LoadTestPlan(options.plan_path);
  if (!options.constants_path.empty() || options.variant) {
    plan.force_model = ResolveAxialShearModel(
        options.constants_path.empty() ? plan.constants_path
                                       : options.constants_path,
        options.variant.value_or(std::string(VariantName(plan.force_model))),
        nullptr);
    // The file the model came from, for the report's record of inputs.
    if (!options.constants_path.empty()) {
      plan.constants_path = options.constants_path;
    }
  }
  if (!options.pressure_log_path.empty()) {
    *log = PressureLogTimes{
        options.pressure_log_path,
        PlanPressureHolds(plan, options.pressure_log_path,
                          DecimalMarkFromFlag(options.decimal_comma))};
  }
  return plan;
}

// "id (reason)" for each test that was not measured.
std::vector<std::string> NotMeasured(const ValidationResult& r) {
  std::vector<std::string> tests;
  for (const TestScore& t : r.tests) {
    if (!t.measured) tests.push_back(fmt::format("{} ({})", t.id, t.reason));
  }
  return tests;
}

// What the command prints of one video.
std::string SummaryText(const VideoValidation& v) {
  const ValidationResult& r = v.result;
  std::string text =
      fmt::format("{}: {} test points (times from {}), {} measured\n",
                  v.measurement.video_path, r.tests.size(), r.times_source,
                  std::count_if(r.tests.begin(), r.tests.end(),
                                [](const TestScore& t) { return t.measured; }));
  for (const std::string& test : NotMeasured(r)) {
    text += fmt::format("  not measured: {}\n", test);
  }
  for (const TestScore& t : r.tests) {
    if (t.measured && !t.predicted) {
      text += fmt::format("  no prediction: {} ({})\n", t.id, t.reason);
    }
  }
  if (!r.mismatched.empty()) {
    text += fmt::format(
        "  not scored, their motion does not fit their plan entries: {}\n",
        fmt::join(r.mismatched, ", "));
  }
  if (!v.plan.skipped_tests.empty()) {
    std::vector<std::string> ids;
    for (const TestPoint& t : v.plan.skipped_tests) ids.push_back(t.id);
    text += fmt::format("  skipped on the bench (as the plan says): {}\n",
                        fmt::join(ids, ", "));
  }
  const CameraProcessing& processing = v.measurement.camera_processing;
  if (!processing.effects.empty()) {
    std::vector<std::string> names;
    for (const ProcessingEffect& e : processing.effects)
      names.push_back(e.name);
    text += fmt::format(
        "  the camera's processing, seen in the footage: {} ({})\n",
        fmt::join(names, "; "),
        processing.tag_scale_at_risk
            ? fmt::format("on the tag's cells of {:.1f} px it may move the "
                          "scale; the report's Calibration says how it is "
                          "checked and carried",
                          processing.tag_cell_px)
            : "the report's Calibration says why none of it moves the "
              "measurement");
  }
  // The lift's parallax: said where it was taken out or the user chose.
  if (v.measurement.lift_corrected ||
      v.lift_correction.mode != LiftCorrectionMode::kAuto) {
    text += fmt::format("  the heads' lift and tilt: their parallax {}\n",
                        v.lift_correction.reason);
  }
  for (int h = 0; h < v.plan.mechanism.NumHeads(); ++h) {
    if (r.model_errors[h].tests == 0) {
      text += fmt::format("  {}: no test scored, so no model error\n",
                          v.plan.mechanism.heads[h].name);
      continue;
    }
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

}  // namespace

void AddValidateCommand(CLI::App* c, ValidateCommandOptions* options) {
  c->add_option("videos", options->video_paths,
                "bench video(s); several get one report each and an index")
      ->required();
  c->add_option("--jobs", options->jobs,
                "videos measured at once (0: one per core)")
      ->capture_default_str();
  AddPlanOption(c, &options->plan_path);
  AddOutOption(c, &options->output_directory,
               "report directory (replaced whole)")
      ->required();
  c->add_option("--constants", options->constants_path,
                "actuator constants (default: the plan's)");
  c->add_option("--pressure-log", options->pressure_log_path,
                "the regulator's log (time_s,p1_UNIT..pN_UNIT, or plain pN in "
                "the plan's unit): test times from it, "
                "its clock aligned by the motion");
  AddRestOption(c, &options->rest_s);
  AddNoRegistrationFlag(c, &options->no_registration);
  CLI::Option* always =
      c->add_flag("--lift-correction", options->lift_correction,
                  "take the parallax of each head's measured lift and tilt "
                  "out of its position always (by default: where the "
                  "heads' lifts over the tests show they leave the plane; "
                  "docs/measurement.md)");
  c->add_flag("--no-lift-correction", options->no_lift_correction,
              "leave the parallax in every head's position, counted in "
              "its uncertainty")
      ->excludes(always);
  AddDecimalCommaFlag(c, &options->decimal_comma);
  c->add_flag("--windows-only", options->windows_only,
              "read only the frames of the tests' windows, seeking between "
              "them, and a few around key frames elsewhere when the windows "
              "show too few for the uncertainty's codec term (needs the "
              "times in the plan)");
  c->add_option("--variant", options->variant,
                ModelVariantNames() + " (default: the plan's)");
}

int RunValidate(const ValidateCommandOptions& options, std::ostream& out) {
  if (options.video_paths.empty()) throw InputError("validate: give a video");
  if (options.jobs < 0) throw InputError("--jobs: must be >= 0");
  VideoValidationOptions validation = options.validation;
  validation.rest_s = options.rest_s;
  validation.windows_only = options.windows_only;
  validation.register_frames = !options.no_registration;
  validation.lift_correction.mode =
      options.lift_correction      ? LiftCorrectionMode::kEveryHead
      : options.no_lift_correction ? LiftCorrectionMode::kNone
                                   : LiftCorrectionMode::kAuto;
  validation.progress = !options.quiet && options.video_paths.size() == 1;
  if (const std::optional<std::string> problem = validation.Problem()) {
    throw InputError("validate: " + *problem);
  }
  std::optional<PressureLogTimes> log;
  const TestPlan plan = LoadValidationPlan(options, &log);
  CheckOutputDirectory(options.output_directory, "--out");
  std::vector<NamedPath> inputs = {
      {"--plan", options.plan_path},
      {"--pressure-log", options.pressure_log_path},
      {"--constants", options.constants_path},
      {"the plan's constants", plan.constants_path},
      {"the plan's intrinsics", plan.calibration.intrinsics_path}};
  for (const std::string& video : options.video_paths) {
    inputs.push_back({"the video", video});
  }
  CheckOutputsSpareInputs(inputs, {}, {{"--out", options.output_directory}});
  const int count = static_cast<int>(options.video_paths.size());
  std::vector<VideoValidation> videos(count);
  if (count == 1) {
    videos[0] = ValidateVideo(plan, options.video_paths[0], log, validation);
  } else {
    // Videos in parallel; one bar for all of them.
    std::atomic<int> done{0};
    ProgressBar progress("videos", count, !options.quiet);
    RunParallelTasks(
        count, options.jobs,
        [&](int i) {
          videos[i] =
              ValidateVideo(plan, options.video_paths[i], log, validation);
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
    WriteValidationIndex(videos, names, report);
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
  for (const VideoValidation& v : videos) {
    if (std::any_of(v.result.tests.begin(), v.result.tests.end(),
                    [](const TestScore& t) { return !t.scored(); })) {
      return kExitSomeTestsNotScored;
    }
  }
  return 0;
}

}  // namespace softbench
