#include "pipelines/commands/synth_forces_command.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <filesystem>
#include <vector>

#include "model/units.h"
#include "pipelines/commands/common_flags.h"
#include "pipelines/commands/model_flags.h"
#include "pipelines/commands/model_selection.h"
#include "pipelines/synthetic/force_logs.h"
#include "util/input_error.h"

namespace softbench {
void AddSynthForcesCommand(CLI::App* command,
                           SynthForcesCommandOptions* options) {
  AddOutOption(command, &options->output_directory,
               "directory for the logs and manifest.yaml (replaced whole)")
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
  AddThreadsOption(command, &options->threads);
}

namespace {

namespace fs = std::filesystem;

// "1.5 GB", "820 MB", "96 kB" (decimal units, as file managers show).
std::string ByteCount(int64_t bytes) {
  const double b = static_cast<double>(bytes);
  if (b >= 1e9) return fmt::format("{:.1f} GB", b / 1e9);
  if (b >= 1e6) return fmt::format("{:.0f} MB", b / 1e6);
  return fmt::format("{:.0f} kB", std::max(1.0, b / 1e3));
}

// The logs are written beside the output folder and swapped in: its parent's
// file system must hold them (the previous logs stay until the swap).
void CheckFreeSpace(const std::string& directory, int64_t bytes) {
  fs::path parent = fs::path(directory).parent_path();
  if (parent.empty()) parent = ".";
  std::error_code error;
  const fs::space_info space = fs::space(parent, error);
  if (error) return;  // CheckOutputDirectory named an unusable folder
  // A margin for the file system's blocks and the estimate's few per cent.
  if (static_cast<double>(bytes) * 1.05 >
      static_cast<double>(space.available)) {
    throw InputError(fmt::format(
        "--out {}: the logs need about {} and its disk has {} free; choose "
        "another folder or a lower --rate",
        directory, ByteCount(bytes),
        ByteCount(static_cast<int64_t>(space.available))));
  }
}

}  // namespace

int RunSynthForces(SynthForcesCommandOptions options, std::ostream& out) {
  ForceLogFilesOptions logs;
  std::string variant;
  const ForceModel model =
      ResolveAxialShearModel(options.constants_path, options.variant, &variant);
  if (!(options.synthetic.sample_rate_hz > 0.0 &&
        options.synthetic.sample_rate_hz <= 1e6)) {
    throw InputError("--rate: must be > 0 and at most 1e6 samples per s");
  }
  logs.synthetic = options.synthetic;
  if (options.noise_only) {
    logs.synthetic = SyntheticForceLogOptions::NoiseOnly(model);
    logs.synthetic.sample_rate_hz = options.synthetic.sample_rate_hz;
    logs.synthetic.seed = options.synthetic.seed;
    logs.synthetic.outlier_fraction = options.synthetic.outlier_fraction;
  }
  logs.synthetic.model = model;
  if (!options.hysteresis_n.empty()) {
    const std::vector<double> h =
        ParseNumberList(options.hysteresis_n, "--hysteresis");
    if (h.size() != 2)
      throw InputError("--hysteresis: give 'axial,shear' in N");
    // The sensor's range is +-100 N (the reader's max_abs_force_n).
    for (double n : h) {
      if (!(n >= 0.0 && n <= 100.0)) {
        throw InputError(fmt::format(
            "--hysteresis: {} N is not a force hysteresis; give two forces "
            "from 0 to 100 N (the sensor's range)",
            n));
      }
    }
    logs.synthetic.hysteresis_axial_n = h[0];
    logs.synthetic.hysteresis_shear_n = h[1];
  }
  MpaPerPressureUnitFlag(options.pressure_unit);  // names the flag
  CheckOutputDirectory(options.output_directory, "--out");
  CheckOutputsSpareInputs({{"--constants", options.constants_path}}, {},
                          {{"--out", options.output_directory}});
  if (options.threads < 0) throw InputError("--threads: must be >= 0");
  logs.pressure_unit = options.pressure_unit;
  logs.model_name = variant;
  logs.combined = options.combined;
  logs.threads = options.threads;
  logs.progress = !options.quiet;
  if (const std::optional<std::string> problem = logs.Problem()) {
    throw InputError("synth-forces: " + *problem);
  }
  // Said, and checked against the disk, before writing: at the sensor's
  // 5.7 kHz the protocol is over a gigabyte.
  const ForceLogFilesSize size = EstimateForceLogFiles(logs);
  CheckFreeSpace(options.output_directory, size.bytes);
  if (!options.quiet) {
    spdlog::info("writing {} tests, {} rows, about {}, to {}", size.tests,
                 size.rows, ByteCount(size.bytes), options.output_directory);
  }
  const ForceLogFiles written =
      WriteForceLogFiles(options.output_directory, logs);
  out << fmt::format("{} tests, {} rows: {}\n", written.tests, written.rows,
                     written.manifest_path);
  return 0;
}

}  // namespace softbench
