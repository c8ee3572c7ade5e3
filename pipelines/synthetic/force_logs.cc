#include "pipelines/synthetic/force_logs.h"

#include <fmt/compile.h>
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <functional>
#include <iterator>
#include <vector>

#include "model/units.h"
#include "pipelines/characterisation/force_log_manifest.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/input_error.h"
#include "util/parallel_tasks.h"
#include "util/progress.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

constexpr const char* kHeader = "time_s,{},fx_n,fy_n,fz_n,tx_nm,ty_nm,tz_nm\n";

// Appends one row in the sensor's export format (micro-second times, the
// pressure sensor's and the Mini40's resolution) after `prefix` (a combined
// log's configuration columns, or nothing).
void AppendRow(std::string_view prefix, const SyntheticRow& row,
               double units_per_mpa, std::string* out) {
  out->append(prefix);
  fmt::format_to(std::back_inserter(*out),
                 FMT_COMPILE("{:.6f},{:.4f},{:.4f},{:.4f},{:.4f},{:.5f},{:.5f},"
                             "{:.5f}\n"),
                 row.time_s, row.pressure_mpa * units_per_mpa, row.force_n[0],
                 row.force_n[1], row.force_n[2], row.torque_nm[0],
                 row.torque_nm[1], row.torque_nm[2]);
}

// The manifest of the tests, each in its own file.
ForceLogManifest Manifest(const std::vector<SyntheticTest>& tests,
                          const std::string& pressure_unit) {
  ForceLogManifest manifest;
  manifest.columns.pressure = "pressure_" + pressure_unit;
  for (const SyntheticTest& test : tests) {
    ForceTest& entry = manifest.tests.emplace_back();
    entry.id = test.id;
    entry.nominal_delta_length_mm = test.nominal_delta_length_mm;
    entry.nominal_theta_rad = test.nominal_theta_rad;
    entry.measured_delta_length_mm = test.delta_length_mm;
    entry.measured_theta_rad = test.theta_rad;
    manifest.files.push_back(test.id + ".csv");
  }
  return manifest;
}

// Test t's rows after `prefix` into `text`.
using GenerateTest =
    std::function<void(int t, std::string_view prefix, std::string* text)>;

void WriteCombined(const fs::path& path,
                   const std::vector<SyntheticTest>& tests,
                   const std::string& header, const GenerateTest& generate,
                   const std::function<void()>& poll) {
  AtomicFileWriter writer(path.string());
  writer.Append(
      "test_id,delta_length_mm,theta_deg,measured_delta_length_mm,"
      "measured_theta_deg," +
      header);
  for (int t = 0; t < static_cast<int>(tests.size()); ++t) {
    const std::string prefix = fmt::format(
        "{},{:.6g},{:.6g},{:.4f},{:.4f},", tests[t].id,
        tests[t].nominal_delta_length_mm, RadToDeg(tests[t].nominal_theta_rad),
        tests[t].delta_length_mm, RadToDeg(tests[t].theta_rad));
    std::string text;
    generate(t, prefix, &text);
    writer.Append(text);
    poll();
  }
  writer.Commit();
}

std::string ManifestComment(const ForceLogFilesOptions& options,
                            size_t num_tests) {
  const ActuatorConstants& c = options.synthetic.model.constants;
  return fmt::format(
      "# Synthetic characterisation logs (softbench synth-forces): {} tests "
      "at {} Hz, seed {}.\n# Truth: {} with A_z {}, W_y {}, k_s {}, k_theta "
      "{}.\n",
      num_tests, options.synthetic.sample_rate_hz, options.synthetic.seed,
      options.model_name, c.axial_area_mm2, c.shear_area_factor_mm2_per_rad,
      c.linear_stiffness_n_per_mm, c.torsional_factor_n_per_rad);
}

}  // namespace

std::optional<std::string> ForceLogFilesOptions::Problem() const {
  if (auto problem = synthetic.Problem()) return "synthetic: " + *problem;
  if (!MpaPerPressureUnit(pressure_unit)) {
    return "pressure_unit: '" + pressure_unit + "' is not " +
           PressureUnitNames();
  }
  if (threads < 0) return "threads: must be >= 0";
  return std::nullopt;
}

ForceLogFilesSize EstimateForceLogFiles(const ForceLogFilesOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  const std::vector<SyntheticTest> tests = SyntheticTests(options.synthetic);
  ForceLogFilesSize size;
  size.tests = static_cast<int>(tests.size());
  for (const SyntheticTest& test : tests) size.rows += test.rows;
  // Bytes per row from the first test's rows formatted as written, at a rate
  // low enough to take a moment (a row's width does not depend on the rate);
  // a combined log's rows also carry the configuration columns.
  SyntheticForceLogOptions sampled = options.synthetic;
  sampled.sample_rate_hz = std::min(sampled.sample_rate_hz, 100.0);
  const std::vector<SyntheticTest> sampled_tests = SyntheticTests(sampled);
  if (sampled_tests.empty() || sampled_tests[0].rows == 0) return size;
  const double units_per_mpa = 1.0 / *MpaPerPressureUnit(options.pressure_unit);
  const std::string_view prefix =
      options.combined ? "t01,-3,30,-3.0000,30.0000," : "";
  int64_t sampled_bytes = 0;
  std::string text;
  GenerateSyntheticTest(sampled, sampled_tests[0], 0,
                        [&](const SyntheticRow& row) {
                          text.clear();
                          AppendRow(prefix, row, units_per_mpa, &text);
                          sampled_bytes += static_cast<int64_t>(text.size());
                        });
  size.bytes = static_cast<int64_t>(static_cast<double>(sampled_bytes) /
                                    static_cast<double>(sampled_tests[0].rows) *
                                    static_cast<double>(size.rows));
  return size;
}

ForceLogFiles WriteForceLogFiles(const std::string& directory_name,
                                 const ForceLogFilesOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  // Written beside and swapped in whole: a failed or killed run leaves the
  // previous logs and manifest as they were, never new logs with an old
  // manifest.
  AtomicDirectory staging(directory_name);
  const fs::path directory(staging.File(""));
  const std::vector<SyntheticTest> tests = SyntheticTests(options.synthetic);
  ForceLogManifest manifest = Manifest(tests, options.pressure_unit);
  const std::string header = fmt::format(kHeader, manifest.columns.pressure);
  ForceLogFiles written;
  written.tests = static_cast<int>(tests.size());
  for (const SyntheticTest& test : tests) written.rows += test.rows;

  const double units_per_mpa = 1.0 / *MpaPerPressureUnit(options.pressure_unit);
  ProgressBar progress("synth-forces", written.rows, options.progress);
  std::atomic<int64_t> rows_done{0};
  const GenerateTest generate = [&](int t, std::string_view prefix,
                                    std::string* text) {
    GenerateSyntheticTest(options.synthetic, tests[t], t,
                          [&](const SyntheticRow& row) {
                            AppendRow(prefix, row, units_per_mpa, text);
                          });
    rows_done += tests[t].rows;
  };
  const auto poll = [&] { progress.Update(rows_done); };
  if (options.combined) {
    manifest.combined_path = "forces.csv";
    WriteCombined(directory / manifest.combined_path, tests, header, generate,
                  poll);
  } else {
    // Tests in parallel, one file each (each test has its own random stream,
    // so the files do not depend on the thread count).
    RunParallelTasks(
        written.tests, options.threads,
        [&](int t) {
          std::string text = header;
          generate(t, "", &text);
          WriteFileAtomically((directory / manifest.files[t]).string(), text);
        },
        poll);
  }
  progress.Finish();
  WriteFileAtomically(
      (directory / "manifest.yaml").string(),
      ForceLogManifestYaml(manifest, options.pressure_unit,
                           ManifestComment(options, tests.size())));
  staging.Commit();
  written.manifest_path = (fs::path(directory_name) / "manifest.yaml").string();
  return written;
}

}  // namespace softbench
