#include "pipelines/characterisation/fit_analysis.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>

#include "util/check.h"
#include "util/input_error.h"
#include "util/parallel_tasks.h"
#include "util/progress.h"

namespace softbench {
namespace {

bool EndsWith(const std::string& text, std::string_view suffix) {
  return text.size() >= suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

int64_t FileBytes(const std::string& path) {
  std::error_code error;
  const auto size = std::filesystem::file_size(path, error);
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

ForceLogManifest LoadInput(const FitAnalysisOptions& options) {
  if (!EndsWith(options.input_path, ".csv")) {
    return LoadForceLogManifest(options.input_path);
  }
  ForceLogManifest manifest;
  manifest.combined_path = options.input_path;
  manifest.columns = options.combined_columns;
  return manifest;
}

// Reads every log, keeping every n-th row when the fit needs rows, with a
// progress bar over the bytes read.
std::vector<ForceRow> ReadLogs(const FitAnalysisOptions& options,
                               const ForceLogManifest& manifest, FitRun* run) {
  const bool combined = !manifest.combined_path.empty();
  const std::vector<std::string> files =
      combined ? std::vector<std::string>{manifest.combined_path}
               : manifest.files;
  int64_t total_bytes = 0;
  for (const std::string& file : files) total_bytes += FileBytes(file);
  ForceLogReadOptions read_options;
  read_options.decimal_mark = options.decimal_mark;
  if (options.fit.loss != FitLoss::kLeastSquares) {
    read_options.keep_every_nth_row = std::max<int64_t>(
        1, EstimateRows(files, total_bytes) / options.robust_rows);
  }
  std::vector<ForceRow> rows;
  std::atomic<int64_t> bytes_done{0};
  ProgressBar progress("reading", total_bytes, options.progress);
  if (combined) {
    // One task (a combined log is read in order), on a worker so that this
    // thread can draw the progress bar.
    RunParallelTasks(
        1, 1,
        [&](int) {
          run->tests = ReadCombinedForceLog(manifest.combined_path,
                                            manifest.columns, read_options,
                                            &run->read, &rows, &bytes_done);
        },
        [&] { progress.Update(bytes_done); });
  } else {
    // One test per task, each with its own summary and kept rows.
    run->tests = manifest.tests;
    const int num_tests = static_cast<int>(run->tests.size());
    std::vector<ForceLogReadSummary> summaries(num_tests);
    std::vector<std::vector<ForceRow>> kept(num_tests);
    RunParallelTasks(
        num_tests, options.threads,
        [&](int t) {
          ReadForceTestCsv(files[t], manifest.columns, read_options, t,
                           &run->tests[t], &summaries[t], &kept[t],
                           &bytes_done);
        },
        [&] { progress.Update(bytes_done); });
    for (int t = 0; t < num_tests; ++t) {
      run->read.Merge(summaries[t]);
      rows.insert(rows.end(), kept[t].begin(), kept[t].end());
    }
  }
  progress.Finish();
  return rows;
}

}  // namespace

std::optional<std::string> FitAnalysisOptions::Problem() const {
  if (input_path.empty()) return "input_path: give a manifest or a CSV";
  if (auto problem = fit.Problem()) return "fit: " + *problem;
  if (robust_rows < 1000) return "robust_rows: keep at least 1000 rows";
  if (!(natural_length_mm > 0.0 && natural_length_mm <= 1000.0)) {
    return "natural_length_mm: must be > 0 and at most 1000 mm (the "
           "actuator's length at rest)";
  }
  if (threads < 0) return "threads: must be >= 0";
  return std::nullopt;
}

FitRun RunFitAnalysis(const FitAnalysisOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  const auto start = std::chrono::steady_clock::now();
  FitRun run;
  run.input_path = options.input_path;
  const ForceLogManifest manifest = LoadInput(options);
  run.mpa_per_unit = manifest.columns.mpa_per_unit;
  run.pressure_unit = manifest.columns.pressure.substr(
      manifest.columns.pressure.rfind('_') + 1);
  const std::vector<ForceRow> rows = ReadLogs(options, manifest, &run);
  for (const std::string& example : run.read.skipped_examples) {
    run.warnings.push_back("skipped " + example);
  }
  if (run.read.rows_skipped > 0) {
    run.warnings.push_back(fmt::format(
        "{} of {} rows skipped (NaN/inf, unparsable or out of range)",
        run.read.rows_skipped, run.read.rows + run.read.rows_skipped));
  }
  ActuatorConstants base;
  base.natural_length_mm = options.natural_length_mm;
  run.models = FitModel::ThesisModels(base);
  for (const FitModel& model : run.models) {
    run.fits.push_back(FitForceModel(model, run.tests, rows, options.fit));
  }
  run.configurations = AnalyseConfigurations(run.tests);
  run.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
          .count();
  return run;
}

}  // namespace softbench
