#include "pipelines/commands/fit_command.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "model/units.h"
#include "pipelines/commands/common_flags.h"
#include "pipelines/commands/model_selection.h"
#include "pipelines/formats/constants_file.h"
#include "pipelines/reports/fit_report.h"
#include "util/atomic_file.h"
#include "util/check.h"
#include "util/csv.h"
#include "util/input_error.h"

namespace softbench {
namespace {

FitLoss ParseLoss(const std::string& name) {
  if (name == "none") return FitLoss::kLeastSquares;
  if (name == "huber") return FitLoss::kHuber;
  if (name == "cauchy") return FitLoss::kCauchy;
  throw InputError("--loss: '" + name + "' is not one of none, huber, cauchy");
}

// --variant names a variant of ModelVariants(); throws InputError listing
// them for any other name, the empty one included.
void CheckVariantName(const std::string& name) {
  if (ForceModelFromVariantName(name, {})) return;
  throw InputError("--variant: '" + name + "' is not a variant; use " +
                   ModelVariantNames());
}

// The fit of the checked variant `name` (RunFitAnalysis fits every one).
const ForceFitSummary& ChosenFit(const FitRun& run, const std::string& name) {
  for (const ForceFitSummary& fit : run.fits) {
    if (fit.model_name == name) return fit;
  }
  SOFTBENCH_CHECK(false) << "no fit of variant '" << name << "'";
}

}  // namespace

void AddFitCommand(CLI::App* command, FitCommandOptions* options) {
  command
      ->add_option("input", options->input_path,
                   "force-log manifest (.yaml) or combined log (.csv)")
      ->required();
  AddOutOption(command, &options->output_path,
               "constants YAML to write (the input of predict, workspace, "
               "validate)");
  command->add_option("--report", options->report_directory,
                      "report directory (tables, fit.json, report.html)");
  command
      ->add_option("--variant", options->variant,
                   "variant whose constants --out gets: " + ModelVariantNames())
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
  command->add_option("--pressure-unit", options->pressure_unit,
                      "combined CSV without manifest: " + PressureUnitNames() +
                          " (default: its pressure_UNIT column's)");
  command
      ->add_option("--axial", options->axial,
                   "combined CSV without manifest: signed axial column")
      ->capture_default_str();
  command
      ->add_option("--shear", options->shear,
                   "combined CSV without manifest: signed shear column")
      ->capture_default_str();
  AddThreadsOption(command, &options->threads);
  AddDecimalCommaFlag(command, &options->decimal_comma);
}

namespace {

// The pressure unit of a combined CSV: --pressure-unit, else the one its
// pressure_UNIT column names, in any case (never assumed). Returned as the
// column writes it, so that it names the column.
std::string CombinedPressureUnit(const FitCommandOptions& flags) {
  if (flags.pressure_unit) return *flags.pressure_unit;
  const CsvReader reader(flags.input_path);
  for (const std::string& column : reader.header()) {
    if (column.starts_with("pressure_") &&
        FindPressureUnit(static_cast<std::string_view>(column).substr(9)) !=
            nullptr) {
      return column.substr(9);
    }
  }
  throw InputError(fmt::format(
      "{}:1: no pressure column with its unit (pressure_UNIT, UNIT one of "
      "{}); rename it, e.g. pressure_psi, or pass --pressure-unit",
      flags.input_path, PressureUnitNames()));
}

}  // namespace

FitAnalysisOptions FitAnalysisOptionsFromFlags(const FitCommandOptions& flags) {
  // Each flag is checked under its own name (the options' own check below
  // words its problems for the library's fields).
  if (!(flags.loss_scale_n > 0.0)) {
    throw InputError("--loss-scale: must be > 0 N");
  }
  if (!(flags.axial_weight >= 0.0)) {
    throw InputError("--axial-weight: must be >= 0");
  }
  if (!(flags.shear_weight >= 0.0)) {
    throw InputError("--shear-weight: must be >= 0");
  }
  if (flags.axial_weight + flags.shear_weight == 0.0) {
    throw InputError(
        "--axial-weight and --shear-weight: both are 0, so nothing is "
        "fitted; give one of them a weight > 0");
  }
  if (flags.robust_rows < 1000) {
    throw InputError("--robust-rows: keep at least 1000 rows");
  }
  if (!(flags.natural_length_mm > 0.0 && flags.natural_length_mm <= 1000.0)) {
    throw InputError(
        "--natural-length: must be > 0 and at most 1000 mm (the actuator's "
        "length at rest)");
  }
  if (flags.threads < 0) throw InputError("--threads: must be >= 0");
  FitAnalysisOptions options;
  options.input_path = flags.input_path;
  options.fit.loss = ParseLoss(flags.loss);
  options.fit.loss_scale_n = flags.loss_scale_n;
  options.fit.axial_weight = flags.axial_weight;
  options.fit.shear_weight = flags.shear_weight;
  options.robust_rows = flags.robust_rows;
  options.natural_length_mm = flags.natural_length_mm;
  options.decimal_mark = DecimalMarkFromFlag(flags.decimal_comma);
  options.threads = flags.threads;
  options.progress = !flags.quiet;
  ForceLogColumns& columns = options.combined_columns;
  if (flags.input_path.ends_with(".csv")) {  // a manifest states its unit
    const std::string unit = CombinedPressureUnit(flags);
    columns.mpa_per_unit = MpaPerPressureUnitFlag(unit);
    columns.pressure = "pressure_" + unit;
  }
  ParseSignedColumn(flags.axial, "--axial", &columns.axial,
                    &columns.axial_sign);
  ParseSignedColumn(flags.shear, "--shear", &columns.shear,
                    &columns.shear_sign);
  if (const std::optional<std::string> problem = options.Problem()) {
    throw InputError("fit: " + *problem);
  }
  return options;
}

namespace {

// The range the logs span: the highest pressure and the largest |dL| and
// |theta| of their configurations.
CharacterisedRange FittedRange(const FitRun& run) {
  CharacterisedRange range{0.0, 0.0, 0.0};
  for (const ForceTest& test : run.tests) {
    range.max_pressure_mpa =
        std::max(range.max_pressure_mpa, test.statistics.max_pressure_mpa);
    range.max_abs_delta_length_mm = std::max(range.max_abs_delta_length_mm,
                                             std::abs(test.delta_length_mm()));
    range.max_abs_theta_rad =
        std::max(range.max_abs_theta_rad, std::abs(test.theta_rad()));
  }
  // A protocol that never bent or stretched still spans a sliver around 0
  // (WhyBendingUnidentifiable refuses the constants of one that never bent).
  range.max_abs_delta_length_mm = std::max(range.max_abs_delta_length_mm, 0.1);
  range.max_abs_theta_rad = std::max(range.max_abs_theta_rad, DegToRad(1.0));
  return range;
}

// W_y and k_theta act only through the bend angle (Eq. 2.7, 2.14): tests
// whose angles span less than this cannot tell them apart from noise, and a
// fit would report whatever the angle sensor's jitter implies, with a
// standard error that looks fine.
constexpr double kMinBendSpanDeg = 5.0;

std::optional<std::string> WhyBendingUnidentifiable(const FitRun& run) {
  double low = INFINITY, high = -INFINITY;
  for (const ForceTest& test : run.tests) {
    low = std::min(low, RadToDeg(test.theta_rad()));
    high = std::max(high, RadToDeg(test.theta_rad()));
  }
  if (high - low >= kMinBendSpanDeg) return std::nullopt;
  return fmt::format(
      "the tests' bend angles span only {:.2f} deg ({:.2f} to {:.2f}), so "
      "W_y and k_theta, which act through the bend, are not identifiable "
      "(the fit's values for them come from the angles' jitter); add tests "
      "at several angles (the thesis: 0 to 30 deg)",
      high - low, low, high);
}

}  // namespace

int RunFit(const FitCommandOptions& options, std::ostream& out) {
  CheckVariantName(options.variant);
  if (!options.output_path.empty()) {
    CheckOutputFile(options.output_path, "--out");
  }
  if (!options.report_directory.empty()) {
    CheckOutputDirectory(options.report_directory, "--report");
  }
  CheckOutputsSpareInputs({{"the force logs", options.input_path}},
                          {{"--out", options.output_path}},
                          {{"--report", options.report_directory}});
  const FitRun run = RunFitAnalysis(FitAnalysisOptionsFromFlags(options));
  for (const std::string& warning : run.warnings) spdlog::warn("{}", warning);
  out << FitTable(run);
  const ForceFitSummary* chosen = &ChosenFit(run, options.variant);
  for (const ForceFitSummary& fit : run.fits) {
    if (!fit.ok) spdlog::warn("{}: {}", fit.model_name, fit.why_not);
    if (fit.ok && fit.standard_errors_caveat) {
      spdlog::warn("{}: {}", fit.model_name, *fit.standard_errors_caveat);
    }
  }
  if (!chosen->ok) {
    throw InputError(fmt::format("{}: {} constants not written: {}",
                                 options.input_path, options.variant,
                                 chosen->why_not));
  }
  if (const std::optional<std::string> why = WhyBendingUnidentifiable(run)) {
    throw InputError(fmt::format("{}: {} constants not written: {}",
                                 options.input_path, options.variant, *why));
  }
  if (const std::optional<std::string> problem = chosen->constants.Problem()) {
    throw InputError(
        fmt::format("{}: the fitted {} constants are not "
                    "physical ({}); check the sensor axes' signs",
                    options.input_path, options.variant, *problem));
  }
  // Written only once every check has passed: a refused fit leaves an
  // earlier report and constants file as they were (issue 30).
  if (!options.report_directory.empty()) {
    WriteFitReport(run, options.report_directory);
    out << fmt::format("report: {}/report.html\n", options.report_directory);
  }
  if (!options.output_path.empty()) {
    ConstantsFile file{chosen->constants, options.variant, FittedRange(run)};
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
