#include "pipelines/fit_command.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "calibration/constants_file.h"
#include "pipelines/force_log_manifest.h"
#include "pipelines/model_selection.h"
#include "util/atomic_file.h"
#include "util/input_error.h"
#include "util/parallel_tasks.h"
#include "util/progress.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

bool EndsWith(const std::string& text, std::string_view suffix) {
  return text.size() >= suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

int64_t FileBytes(const std::string& path) {
  std::error_code error;
  const auto size = fs::file_size(path, error);
  if (error) {
    throw InputError(path + ": cannot read the file (" + error.message() +
                     "); check the manifest's file names");
  }
  return static_cast<int64_t>(size);
}

// Rows in a set of files, estimated from their size and the first file's
// mean line length, to spread the rows kept for a robust fit evenly.
int64_t EstimateRows(const std::vector<std::string>& files, int64_t bytes) {
  std::ifstream stream(files.front(), std::ios::binary);
  std::string sample(1 << 16, '\0');
  stream.read(sample.data(), static_cast<std::streamsize>(sample.size()));
  sample.resize(static_cast<size_t>(stream.gcount()));
  const int64_t lines = std::count(sample.begin(), sample.end(), '\n');
  return lines > 1 ? bytes * lines / static_cast<int64_t>(sample.size())
                   : bytes / 40;
}

FitLoss ParseLoss(const std::string& name) {
  if (name == "none") return FitLoss::kLeastSquares;
  if (name == "huber") return FitLoss::kHuber;
  if (name == "cauchy") return FitLoss::kCauchy;
  throw InputError("--loss: '" + name + "' is not one of none, huber, cauchy");
}

}  // namespace

void AddFitCommand(CLI::App* app, FitCommandOptions* options) {
  CLI::App* command = app->add_subcommand(
      "fit",
      "Fit the actuator constants from force-sensor logs (thesis ch. 3)");
  command
      ->add_option("input", options->input_path,
                   "force-log manifest (.yaml) or combined log (.csv)")
      ->required();
  command->add_option("--output", options->output_path,
                      "constants YAML to write (the input of predict, "
                      "workspace, validate)");
  command->add_option("--report", options->report_directory,
                      "report directory (tables, fit.json, report.html)");
  command
      ->add_option("--variant", options->variant,
                   "variant whose constants --output gets: small-angle, "
                   "full-trig, variable-arm")
      ->capture_default_str();
  command
      ->add_option("--loss", options->loss,
                   "none (least squares, exact), huber or cauchy (robust, "
                   "Ceres)")
      ->capture_default_str();
  command
      ->add_option("--loss-scale", options->loss_scale_n,
                   "residual [N] where the robust loss turns robust")
      ->capture_default_str();
  command
      ->add_option("--axial-weight", options->axial_weight,
                   "weight of axial residuals")
      ->capture_default_str();
  command
      ->add_option("--shear-weight", options->shear_weight,
                   "weight of shear residuals")
      ->capture_default_str();
  command
      ->add_option("--robust-rows", options->robust_rows,
                   "rows kept in memory for a robust fit")
      ->capture_default_str();
  command
      ->add_option("--natural-length", options->natural_length_mm,
                   "L0 [mm] of the variable-arm variant (Eq. 3.3)")
      ->capture_default_str();
  command
      ->add_option("--pressure-unit", options->pressure_unit,
                   "combined CSV without manifest: psi, kpa or mpa")
      ->capture_default_str();
  command
      ->add_option("--axial", options->axial,
                   "combined CSV without manifest: signed axial column")
      ->capture_default_str();
  command
      ->add_option("--shear", options->shear,
                   "combined CSV without manifest: signed shear column")
      ->capture_default_str();
  command->add_option("--threads", options->threads, "worker threads (0: all)")
      ->capture_default_str();
}

FitRun RunFitAnalysis(const FitCommandOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  ForceFitOptions fit_options;
  fit_options.loss = ParseLoss(options.loss);
  fit_options.loss_scale_n = options.loss_scale_n;
  fit_options.axial_weight = options.axial_weight;
  fit_options.shear_weight = options.shear_weight;
  if (const std::optional<std::string> problem = fit_options.Check()) {
    throw InputError("fit: " + *problem);
  }
  if (options.robust_rows < 1000) {
    throw InputError("--robust-rows: keep at least 1000 rows");
  }
  if (options.threads < 0) throw InputError("--threads: must be >= 0");
  ActuatorConstants base;
  base.natural_length_mm = options.natural_length_mm;
  if (!(base.natural_length_mm > 0.0)) {
    throw InputError("--natural-length: must be > 0 mm");
  }

  FitRun run;
  run.input_path = options.input_path;
  ForceLogManifest manifest;
  if (EndsWith(options.input_path, ".csv")) {
    manifest.combined_path = options.input_path;
    manifest.columns.mpa_per_pressure_unit =
        MpaPerPressureUnit(options.pressure_unit);
    manifest.columns.pressure = "pressure_" + options.pressure_unit;
    ParseSignedColumn(options.axial, "--axial", &manifest.columns.axial,
                      &manifest.columns.axial_sign);
    ParseSignedColumn(options.shear, "--shear", &manifest.columns.shear,
                      &manifest.columns.shear_sign);
  } else {
    manifest = LoadForceLogManifest(options.input_path);
  }
  run.pressure_unit_mpa = manifest.columns.mpa_per_pressure_unit;
  run.pressure_unit = manifest.columns.pressure.substr(
      manifest.columns.pressure.rfind('_') + 1);

  const bool combined = !manifest.combined_path.empty();
  const std::vector<std::string> files =
      combined ? std::vector<std::string>{manifest.combined_path}
               : manifest.files;
  int64_t total_bytes = 0;
  for (const std::string& file : files) total_bytes += FileBytes(file);
  ForceLogReadOptions read_options;
  if (fit_options.loss != FitLoss::kLeastSquares) {
    read_options.keep_every_nth_row = std::max<int64_t>(
        1, EstimateRows(files, total_bytes) / options.robust_rows);
  }

  std::vector<ForceRow> rows;
  std::atomic<int64_t> bytes_done{0};
  ProgressBar progress("reading", total_bytes, !options.quiet);
  if (combined) {
    // One task (a combined log is read in order), on a worker so that this
    // thread can draw the progress bar.
    RunParallelTasks(
        1, 1,
        [&](int) {
          run.tests =
              ReadCombinedForceLog(manifest.combined_path, manifest.columns,
                                   read_options, &run.read, &rows, &bytes_done);
        },
        [&] { progress.Update(bytes_done); });
  } else {
    // One test per task, each with its own summary and kept rows.
    run.tests = manifest.tests;
    const int num_tests = static_cast<int>(run.tests.size());
    std::vector<ForceLogReadSummary> summaries(num_tests);
    std::vector<std::vector<ForceRow>> kept(num_tests);
    RunParallelTasks(
        num_tests, options.threads,
        [&](int t) {
          ReadForceTestCsv(files[t], manifest.columns, read_options, t,
                           &run.tests[t], &summaries[t], &kept[t], &bytes_done);
        },
        [&] { progress.Update(bytes_done); });
    for (int t = 0; t < num_tests; ++t) {
      run.read.Merge(summaries[t]);
      rows.insert(rows.end(), kept[t].begin(), kept[t].end());
    }
  }
  progress.Finish();
  for (const std::string& example : run.read.skipped_examples) {
    spdlog::warn("skipped {}", example);
  }
  if (run.read.rows_skipped > 0) {
    spdlog::warn("{} of {} rows skipped (NaN/inf, unparsable or out of range)",
                 run.read.rows_skipped, run.read.rows + run.read.rows_skipped);
  }

  run.models = FitModel::ThesisModels(base);
  for (const FitModel& model : run.models) {
    run.fits.push_back(FitForceModel(model, run.tests, rows, fit_options));
  }
  run.configurations = AnalyseConfigurations(run.tests);
  run.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  return run;
}

int RunFit(const FitCommandOptions& options, std::ostream& out) {
  ResolveAxialShearModel("", options.variant, nullptr);  // checks the name
  const FitRun run = RunFitAnalysis(options);
  out << FitTable(run);
  const ForceFitSummary* chosen = nullptr;
  for (const ForceFitSummary& fit : run.fits) {
    if (fit.model_name == options.variant) chosen = &fit;
    if (!fit.ok) spdlog::warn("{}: {}", fit.model_name, fit.why_not);
  }
  if (!options.report_directory.empty()) {
    WriteFitReport(run, options.report_directory);
    out << fmt::format("report: {}/report.html\n", options.report_directory);
  }
  if (!chosen->ok) {
    throw InputError(fmt::format("{}: {} constants not written: {}",
                                 options.input_path, options.variant,
                                 chosen->why_not));
  }
  if (const std::optional<std::string> problem = chosen->constants.Check()) {
    throw InputError(
        fmt::format("{}: the fitted {} constants are not "
                    "physical ({}); check the sensor axes' signs",
                    options.input_path, options.variant, *problem));
  }
  if (!options.output_path.empty()) {
    ConstantsFile file{chosen->constants, options.variant};
    WriteFileAtomically(
        options.output_path,
        ConstantsYaml(
            file,
            fmt::format("# Fitted by softbench fit from {} ({} rows, {}).\n"
                        "# Axial R^2 {:.4f}, RMSE {:.3f} N; shear R^2 {:.4f}, "
                        "RMSE {:.3f} N.\n",
                        options.input_path, chosen->rows, chosen->method,
                        chosen->directions[kAxial].r_squared,
                        chosen->directions[kAxial].rmse_n,
                        chosen->directions[kShear].r_squared,
                        chosen->directions[kShear].rmse_n)));
    out << fmt::format("constants ({}): {}\n", options.variant,
                       options.output_path);
  }
  return 0;
}

}  // namespace softbench
