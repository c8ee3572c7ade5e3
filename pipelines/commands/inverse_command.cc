#include "pipelines/commands/inverse_command.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>

#include "model/inverse.h"
#include "pipelines/commands/model_flags.h"
#include "util/input_error.h"

namespace softbench {
namespace {

std::string FormatPressures(const Eigen::VectorXd& pressures_mpa,
                            const ResolvedModel& resolved) {
  std::string text;
  for (int k = 0; k < pressures_mpa.size(); ++k) {
    text += fmt::format("{}p{} = {:.4f}", k == 0 ? "" : ", ", k + 1,
                        pressures_mpa[k] / resolved.mpa_per_unit);
  }
  return text + " " + resolved.pressure_unit;
}

}  // namespace

void AddInverseCommand(CLI::App* command, InverseCommandOptions* options) {
  AddModelSelectionOptions(command, &options->model);
  command
      ->add_option("--target", options->target,
                   "y,z in mm for each head in file order, e.g. -0.5,0.8")
      ->required();
  command->add_option("--max", options->max_pressure,
                      "highest allowed pressure, in --pressure-unit "
                      "(default: 6 psi, the thesis's regulator limit)");
}

int RunInverse(const InverseCommandOptions& options, std::ostream& out) {
  const ResolvedModel resolved = ResolveModel(options.model);
  RequirePressureUnit(resolved, "the answer");
  const std::vector<double> target =
      ParseNumberList(options.target, "--target");
  const int n = resolved.mechanism.NumUnknowns();
  if (static_cast<int>(target.size()) != n) {
    throw InputError(fmt::format(
        "--target: {} number(s) given but mechanism '{}' has {} head(s); give "
        "y,z for each ({} numbers)",
        target.size(), resolved.mechanism.name, n / 2, n));
  }
  // A head moves millimetres; a target a metre away is a typo, whose squared
  // distance would overflow the solver's cost.
  constexpr double kMaxTargetMm = 1000.0;
  for (double value : target) {
    if (!(std::abs(value) <= kMaxTargetMm)) {
      throw InputError(fmt::format(
          "--target: {} mm is not a position a head on a bench can be "
          "asked for; give y,z in mm from rest, within +-{} mm",
          value, kMaxTargetMm));
    }
  }
  InverseOptions inverse_options;
  if (options.max_pressure) {
    if (!(*options.max_pressure > 0.0)) {
      throw InputError("--max: must be a number > 0, in --pressure-unit");
    }
    if (const std::optional<std::string> why =
            ImplausiblePressure(*options.max_pressure, resolved.mpa_per_unit,
                                resolved.pressure_unit)) {
      throw InputError("--max: " + *why);
    }
    inverse_options.max_pressure_mpa =
        *options.max_pressure * resolved.mpa_per_unit;
  }
  const EquilibriumProblem problem(resolved.mechanism, resolved.force_model);
  const Eigen::VectorXd target_mm =
      Eigen::Map<const Eigen::VectorXd>(target.data(), n);
  const InverseResult result =
      SolvePressuresForTarget(problem, target_mm, inverse_options);
  if (!result.solved) {
    throw InputError(fmt::format(
        "inverse: the model has no equilibrium at any start within 0 .. "
        "{:.4g} {} ({}); lower --max toward the characterised {:.4g} {}",
        inverse_options.max_pressure_mpa / resolved.mpa_per_unit,
        resolved.pressure_unit, result.message,
        resolved.range.max_pressure_mpa / resolved.mpa_per_unit,
        resolved.pressure_unit));
  }
  if (const std::optional<std::string> beyond = OutsideCharacterisedRange(
          resolved.range, problem, result.pressures_mpa,
          result.displacements_mm)) {
    spdlog::warn(
        "the answer lies beyond the range the constants were characterised "
        "over ({}): the model extrapolates there",
        *beyond);
  }
  if (result.reachable) {
    out << fmt::format(
        "reachable: {} ({}; {:.2e} mm from the target)\n",
        FormatPressures(result.pressures_mpa, resolved),
        FormatHeadPositions(resolved.mechanism, result.displacements_mm),
        result.distance_mm);
    return 0;
  }
  out << fmt::format(
      "unreachable within 0 .. {:.4g} {}: the closest reachable point is {} "
      "({:.4f} mm from the target), at {}\n",
      inverse_options.max_pressure_mpa / resolved.mpa_per_unit,
      resolved.pressure_unit,
      FormatHeadPositions(resolved.mechanism, result.displacements_mm),
      result.distance_mm, FormatPressures(result.pressures_mpa, resolved));
  return kExitUnreachable;
}

}  // namespace softbench
