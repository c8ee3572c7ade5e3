#include "pipelines/commands/predict_command.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "model/equilibrium.h"
#include "pipelines/commands/command_output.h"
#include "pipelines/commands/model_flags.h"
#include "pipelines/formats/prediction_table.h"
#include "pipelines/formats/pressure_csv.h"
#include "util/input_error.h"

namespace softbench {

void AddPredictCommand(CLI::App* command, PredictOptions* options) {
  AddModelSelectionOptions(command, &options->model);
  command->add_option("--input", options->input_path,
                      "CSV of pressures with columns p1..pN");
  command->add_option("--output", options->output_path,
                      "predictions CSV to write ('-' for standard output)");
  command->add_option("--pressures", options->pressures,
                      "one configuration, e.g. 6,6,0, printed for people");
}

int RunPredict(const PredictOptions& options, std::ostream& out) {
  if (options.pressures.empty() == options.input_path.empty()) {
    throw InputError("predict: give either --pressures or --input");
  }
  if (!options.input_path.empty() && options.output_path.empty()) {
    throw InputError("predict: --input needs --output (a CSV path, or '-')");
  }
  const ResolvedModel resolved = ResolveModel(options.model);
  const Mechanism& mechanism = resolved.mechanism;
  const int num_actuators = mechanism.NumActuators();

  std::vector<Eigen::VectorXd> rows;
  if (!options.pressures.empty()) {
    const std::vector<double> values =
        ParseNumberList(options.pressures, "--pressures");
    if (static_cast<int>(values.size()) != num_actuators) {
      throw InputError(fmt::format(
          "--pressures: {} values given but mechanism '{}' has {} actuators",
          values.size(), mechanism.name, num_actuators));
    }
    for (double p : values) {
      if (p < 0.0) {
        throw InputError("--pressures: pressures are gauge pressures >= 0");
      }
    }
    rows.push_back(
        Eigen::Map<const Eigen::VectorXd>(values.data(), num_actuators));
  } else {
    rows = ReadPressureRows(options.input_path, num_actuators, nullptr);
  }

  const EquilibriumProblem problem(mechanism, resolved.force_model);
  EquilibriumSolver solver(problem);
  PredictionTable table(mechanism);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(problem.NumUnknowns());
  int not_converged = 0;
  for (const Eigen::VectorXd& row : rows) {
    const Eigen::VectorXd pressures_mpa = row * resolved.mpa_per_unit;
    // Rows are often neighbours; start from the previous solution and fall
    // back to the rest state.
    EquilibriumSummary summary = solver.Solve(pressures_mpa, &x);
    if (!summary.converged()) {
      x.setZero();
      summary = solver.Solve(pressures_mpa, &x);
    }
    if (!summary.converged()) {
      ++not_converged;
      x.setZero();
    }
    table.AddRow(row, x, summary);
    if (!options.pressures.empty()) {
      out << fmt::format("{} {}, p = ({}) {}: ", mechanism.name,
                         resolved.model_name, options.pressures,
                         resolved.pressure_unit)
          << (summary.converged() ? FormatHeadPositions(mechanism, x)
                                  : "no equilibrium found")
          << " [" << summary.Message() << "]\n";
    }
  }
  if (!options.output_path.empty()) {
    WriteCommandOutput(options.output_path, table.text(), out);
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
