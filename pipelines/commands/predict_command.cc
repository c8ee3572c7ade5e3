#include "pipelines/commands/predict_command.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "model/prediction.h"
#include "pipelines/commands/command_output.h"
#include "pipelines/commands/common_flags.h"
#include "pipelines/commands/model_flags.h"
#include "pipelines/formats/mechanism_io.h"
#include "pipelines/formats/prediction_table.h"
#include "pipelines/formats/pressure_csv.h"
#include "util/input_error.h"

namespace softbench {

void AddPredictCommand(CLI::App* command, PredictOptions* options) {
  AddModelSelectionOptions(command, &options->model);
  command->add_option("input", options->input_path,
                      "CSV of pressures with columns p1_UNIT..pN_UNIT (e.g. "
                      "p1_psi), or p1..pN with --pressure-unit");
  AddOutOption(command, &options->output_path,
               "predictions CSV to write ('-' for standard output)");
  command->add_option("--pressures", options->pressures,
                      "one configuration, e.g. 6,6,0, printed for people");
  AddDecimalCommaFlag(command, &options->decimal_comma);
}

namespace {

// Why a prediction is out of reach, for the one-line answer.
std::string BeyondReachWhy(const ReachCheck& reach,
                           const ResolvedModel& resolved) {
  const double max_in_unit =
      resolved.range.max_pressure_mpa / resolved.mpa_per_unit;
  if (!std::isfinite(reach.distance_mm)) {
    return fmt::format(
        "not shown to lie where pressures up to the characterised {:.4g} {} "
        "reach",
        max_in_unit, resolved.pressure_unit);
  }
  return fmt::format(
      "{:.4g} mm from the nearest position that pressures up to the "
      "characterised {:.4g} {} reach",
      reach.distance_mm, max_in_unit, resolved.pressure_unit);
}

// The command line's promises checked before any work: one input, and an
// --out that can be written and spares the inputs.
void CheckPredictFlags(const PredictOptions& options) {
  if (options.pressures.empty() == options.input_path.empty()) {
    throw InputError(
        "predict: give either a pressures CSV or --pressures (one of them)");
  }
  if (!options.input_path.empty() && options.output_path.empty()) {
    throw InputError(
        "predict: a pressures CSV needs --out (a CSV path, or '-')");
  }
  if (!options.output_path.empty()) {
    CheckOutputFile(options.output_path, "--out");
    const std::vector<std::string> builtins = BuiltinMechanismNames();
    const bool builtin = std::find(builtins.begin(), builtins.end(),
                                   options.model.mechanism) != builtins.end();
    CheckOutputsSpareInputs(
        {{"the pressures CSV", options.input_path},
         {"--constants", options.model.constants_path},
         {"--mechanism", builtin ? "" : options.model.mechanism}},
        {{"--out", options.output_path}}, {});
  }
}

// The pressures to predict: --pressures (one configuration) or the CSV's
// rows, with the unit they are in.
PressureRows PredictInputRows(const PredictOptions& options,
                              const ResolvedModel& resolved) {
  const Mechanism& mechanism = resolved.mechanism;
  const int num_actuators = mechanism.NumActuators();
  if (options.pressures.empty()) {
    PressureCsvOptions csv;
    csv.num_actuators = num_actuators;
    if (!resolved.pressure_unit.empty())
      csv.stated_unit = resolved.pressure_unit;
    csv.how_to_state = "or pass --pressure-unit";
    csv.decimal_mark = DecimalMarkFromFlag(options.decimal_comma);
    return ReadPressureRows(options.input_path, csv);
  }
  RequirePressureUnit(resolved, "--pressures");
  const std::vector<double> values =
      ParseNumberList(options.pressures, "--pressures");
  if (static_cast<int>(values.size()) != num_actuators) {
    throw InputError(fmt::format(
        "--pressures: {} values given but mechanism '{}' has {} actuators",
        values.size(), mechanism.name, num_actuators));
  }
  for (double p : values) {
    if (const std::optional<std::string> why = ImplausiblePressure(
            p, resolved.mpa_per_unit, resolved.pressure_unit)) {
      throw InputError("--pressures: " + *why);
    }
  }
  PressureRows read;
  read.rows.emplace_back(
      Eigen::Map<const Eigen::VectorXd>(values.data(), num_actuators));
  read.unit = resolved.pressure_unit;
  read.mpa_per_unit = resolved.mpa_per_unit;
  return read;
}

}  // namespace

int RunPredict(const PredictOptions& options, std::ostream& out) {
  CheckPredictFlags(options);
  const ResolvedModel resolved = ResolveModel(options.model);
  const Mechanism& mechanism = resolved.mechanism;
  const PressureRows read = PredictInputRows(options, resolved);
  const std::vector<Eigen::VectorXd>& rows = read.rows;
  const std::string& unit = read.unit;
  const double mpa_per_unit = read.mpa_per_unit;

  const EquilibriumProblem problem(mechanism, resolved.force_model);
  std::vector<Eigen::VectorXd> rows_mpa;
  rows_mpa.reserve(rows.size());
  for (const Eigen::VectorXd& row : rows)
    rows_mpa.emplace_back(row * mpa_per_unit);
  const std::vector<Prediction> predictions =
      PredictEquilibria(problem, resolved.range, rows_mpa);
  PredictionTable table(mechanism, unit);
  int not_converged = 0;
  int outside = 0;
  std::string first_outside;
  int beyond_reach = 0;
  double first_beyond_reach = 0.0;
  for (size_t i = 0; i < rows.size(); ++i) {
    const Prediction& p = predictions[i];
    const bool converged = p.summary.converged();
    not_converged += converged ? 0 : 1;
    if (p.outside_range && outside++ == 0) first_outside = *p.outside_range;
    if (converged && !p.reach.within && beyond_reach++ == 0) {
      first_beyond_reach = p.reach.distance_mm;
    }
    table.AddRow(rows[i], p.x, p.summary, !p.outside_range, p.reach.within);
    if (!options.pressures.empty()) {
      out << fmt::format("{} {}, p = ({}) {}: ", mechanism.name,
                         resolved.model_name, options.pressures, unit)
          << (converged ? FormatHeadPositions(mechanism, p.x)
                        : "no equilibrium found")
          << " [" << p.summary.Message() << "]"
          << (converged && !p.reach.within
                  ? " BEYOND REACH: " + BeyondReachWhy(p.reach, resolved)
                  : "")
          << "\n";
    }
  }
  if (!options.output_path.empty()) {
    WriteCommandOutput(options.output_path, table.text(), out);
  }
  if (outside > 0) {
    spdlog::warn(
        "{} of {} configurations lie beyond the range the constants were "
        "characterised over ({}): the model extrapolates there{}",
        outside, rows.size(), first_outside,
        options.output_path.empty() ? "" : "; their rows have in_range = 0");
  }
  if (beyond_reach > 0) {
    spdlog::warn(
        "{} of {} configurations put the heads beyond the mechanism's reach "
        "(where no pressures up to the characterised {:.4g} {} hold them; "
        "the first {}): the model is extrapolated past anything the bench "
        "can show{}",
        beyond_reach, rows.size(),
        resolved.range.max_pressure_mpa / mpa_per_unit, unit,
        std::isfinite(first_beyond_reach)
            ? fmt::format("{:.4g} mm beyond it", first_beyond_reach)
            : std::string("not shown to lie within it"),
        options.output_path.empty() ? ""
                                    : "; their rows have within_reach = 0");
  }
  if (not_converged > 0) {
    spdlog::warn(
        "{} of {} configurations did not converge; their rows have "
        "converged = 0 and nan positions",
        not_converged, rows.size());
  }
  return 0;
}

}  // namespace softbench
