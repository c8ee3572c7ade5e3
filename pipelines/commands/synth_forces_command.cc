#include "pipelines/commands/synth_forces_command.h"

#include <fmt/compile.h>
#include <fmt/format.h>

#include <atomic>
#include <filesystem>
#include <iterator>

#include "model/units.h"
#include "pipelines/characterisation/force_log_manifest.h"
#include "pipelines/commands/model_flags.h"
#include "pipelines/commands/model_selection.h"
#include "util/atomic_file.h"
#include "util/input_error.h"
#include "util/parallel_tasks.h"
#include "util/progress.h"

namespace softbench {
namespace {

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

}  // namespace

void AddSynthForcesCommand(CLI::App* command,
                           SynthForcesCommandOptions* options) {
  command
      ->add_option("--output", options->output_directory,
                   "directory for the logs and manifest.yaml")
      ->required();
  command->add_option("--constants", options->constants_path,
                      "the true constants (default: the thesis's)");
  command->add_option("--variant", options->variant, ModelVariantNames());
  SyntheticForceLogOptions& s = options->synthetic;
  command->add_option("--rate", s.sample_rate_hz, "samples per second")
      ->capture_default_str();
  command->add_option("--seed", s.seed, "random seed")->capture_default_str();
  command
      ->add_option("--pressure-unit", options->pressure_unit,
                   "unit of the pressure column: " + PressureUnitNames())
      ->capture_default_str();
  command->add_flag("--combined", options->combined,
                    "write one CSV with configuration columns");
  command->add_flag("--noise-only", options->noise_only,
                    "only sensor noise: no regulator dynamics, configuration "
                    "errors, asymmetry or hysteresis");
  command
      ->add_option("--compression-area-factor", s.compression_area_factor,
                   "A_z in compression over A_z in extension")
      ->capture_default_str();
  command->add_option("--hysteresis", options->hysteresis_n,
                      "force added on the way down, 'axial,shear' in N "
                      "(default 0.3,0.1)");
  command
      ->add_option("--outlier-fraction", s.outlier_fraction,
                   "fraction of rows replaced by gross outliers")
      ->capture_default_str();
  command->add_option("--threads", options->threads, "worker threads (0: all)")
      ->capture_default_str();
}

int RunSynthForces(SynthForcesCommandOptions options, std::ostream& out) {
  SyntheticForceLogOptions& synthetic = options.synthetic;
  std::string variant;
  const ForceModel model =
      ResolveAxialShearModel(options.constants_path, options.variant, &variant);
  const ActuatorConstants& constants = model.constants;
  const SyntheticForceLogOptions defaults = synthetic;
  if (options.noise_only) {
    synthetic = SyntheticForceLogOptions::NoiseOnly(model);
    synthetic.sample_rate_hz = defaults.sample_rate_hz;
    synthetic.seed = defaults.seed;
    synthetic.outlier_fraction = defaults.outlier_fraction;
  }
  synthetic.model = model;
  if (!options.hysteresis_n.empty()) {
    const std::vector<double> h =
        ParseNumberList(options.hysteresis_n, "--hysteresis");
    if (h.size() != 2)
      throw InputError("--hysteresis: give 'axial,shear' in N");
    synthetic.hysteresis_axial_n = h[0];
    synthetic.hysteresis_shear_n = h[1];
  }
  if (const std::optional<std::string> problem = synthetic.Check()) {
    throw InputError("synth-forces: " + *problem);
  }
  const double units_per_mpa =
      1.0 / MpaPerPressureUnitFlag(options.pressure_unit);
  if (options.threads < 0) throw InputError("--threads: must be >= 0");

  std::error_code error;
  std::filesystem::create_directories(options.output_directory, error);
  if (error) {
    throw InputError(options.output_directory + ": cannot create (" +
                     error.message() + ")");
  }
  const std::filesystem::path directory(options.output_directory);
  const std::vector<SyntheticTest> tests = SyntheticTests(synthetic);
  ForceLogManifest manifest;
  manifest.columns.pressure = "pressure_" + options.pressure_unit;
  for (const SyntheticTest& test : tests) {
    ForceTest& entry = manifest.tests.emplace_back();
    entry.id = test.id;
    entry.nominal_delta_length_mm = test.nominal_delta_length_mm;
    entry.nominal_theta_rad = test.nominal_theta_rad;
    entry.measured_delta_length_mm = test.delta_length_mm;
    entry.measured_theta_rad = test.theta_rad;
    manifest.files.push_back(test.id + ".csv");
  }
  const std::string header = fmt::format(kHeader, manifest.columns.pressure);
  int64_t total_rows = 0;
  for (const SyntheticTest& test : tests) total_rows += test.rows;

  ProgressBar progress("synth-forces", total_rows, !options.quiet);
  std::atomic<int64_t> rows_done{0};
  const auto generate = [&](int t, std::string_view prefix, std::string* text) {
    GenerateSyntheticTest(synthetic, tests[t], t, [&](const SyntheticRow& row) {
      AppendRow(prefix, row, units_per_mpa, text);
    });
    rows_done += tests[t].rows;
  };

  if (options.combined) {
    manifest.combined_path = "forces.csv";
    AtomicFileWriter writer((directory / manifest.combined_path).string());
    writer.Append(
        "test_id,delta_length_mm,theta_deg,measured_delta_length_mm,"
        "measured_theta_deg," +
        header);
    for (int t = 0; t < static_cast<int>(tests.size()); ++t) {
      const std::string prefix =
          fmt::format("{},{:.6g},{:.6g},{:.4f},{:.4f},", tests[t].id,
                      tests[t].nominal_delta_length_mm,
                      RadToDeg(tests[t].nominal_theta_rad),
                      tests[t].delta_length_mm, RadToDeg(tests[t].theta_rad));
      std::string text;
      generate(t, prefix, &text);
      writer.Append(text);
      progress.Update(rows_done);
    }
    writer.Commit();
  } else {
    // Tests in parallel, one file each (each test has its own random stream,
    // so the files do not depend on the thread count).
    RunParallelTasks(
        static_cast<int>(tests.size()), options.threads,
        [&](int t) {
          std::string text = header;
          generate(t, "", &text);
          WriteFileAtomically((directory / manifest.files[t]).string(), text);
        },
        [&] { progress.Update(rows_done); });
  }
  progress.Finish();

  const std::string manifest_path = (directory / "manifest.yaml").string();
  WriteFileAtomically(
      manifest_path,
      ForceLogManifestYaml(
          manifest, options.pressure_unit,
          fmt::format("# Synthetic characterisation logs (softbench "
                      "synth-forces): {} tests at {} Hz, seed {}.\n# Truth: "
                      "{} with A_z {}, W_y {}, k_s {}, k_theta {}.\n",
                      tests.size(), synthetic.sample_rate_hz, synthetic.seed,
                      variant, constants.axial_area_mm2,
                      constants.shear_area_factor_mm2_per_rad,
                      constants.linear_stiffness_n_per_mm,
                      constants.torsional_factor_n_per_rad)));
  out << fmt::format("{} tests, {} rows: {}\n", tests.size(), total_rows,
                     manifest_path);
  return 0;
}

}  // namespace softbench
