#include "pipelines/commands/workspace_command.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "model/workspace.h"
#include "pipelines/commands/command_output.h"
#include "pipelines/commands/common_flags.h"
#include "pipelines/commands/model_flags.h"
#include "pipelines/formats/prediction_table.h"
#include "util/input_error.h"

namespace softbench {

void AddWorkspaceCommand(CLI::App* command, WorkspaceCommandOptions* options) {
  AddModelSelectionOptions(command, &options->model);
  command
      ->add_option("--max", options->max_pressure,
                   "highest pressure level, in --pressure-unit")
      ->capture_default_str();
  command
      ->add_option("--step", options->step,
                   "spacing of pressure levels, in --pressure-unit")
      ->capture_default_str();
  AddThreadsOption(command, &options->threads);
  AddOutOption(command, &options->output_path,
               "map CSV to write ('-' for standard output)");
}

namespace {

// The number of --step intervals up to --max, checked: a whole number, and
// not so many configurations that the map would not finish.
constexpr double kMaxReachChecks = 2e5;

int CheckedIntervals(const WorkspaceCommandOptions& options, int num_actuators,
                     double mpa_per_unit, std::string_view pressure_unit,
                     double max_in_range) {
  if (!(options.step > 0.0) || !std::isfinite(options.step)) {
    throw InputError("--step: must be a number > 0");
  }
  if (const std::optional<std::string> why = ImplausiblePressure(
          options.max_pressure, mpa_per_unit, pressure_unit)) {
    throw InputError("--max: " + *why);
  }
  if (options.step > options.max_pressure && options.max_pressure > 0.0) {
    throw InputError(fmt::format(
        "--step {} is larger than --max {}; choose a step that divides the "
        "range",
        options.step, options.max_pressure));
  }
  const double intervals = options.max_pressure / options.step;
  const int64_t num_intervals = std::llround(intervals);
  if (std::abs(intervals - num_intervals) > 1e-9 * std::max(1.0, intervals)) {
    throw InputError(fmt::format(
        "--max {} is not a whole number of --step {}; choose a step that "
        "divides the range",
        options.max_pressure, options.step));
  }
  if (options.threads < 0) throw InputError("--threads: must be >= 0");
  const double count = std::pow(num_intervals + 1.0, num_actuators);
  if (count > 5e7) {
    throw InputError(fmt::format(
        "--step: {} levels for {} actuators make {:.3g} configurations; use "
        "a coarser step",
        num_intervals + 1, num_actuators, count));
  }
  // Each configuration beyond the characterised pressures also costs a
  // reach check (a bounded inverse solve, about 1 ms): refused before any
  // work when they would take minutes.
  const double levels_in_range =
      std::floor(max_in_range / options.step * (1.0 + 1e-9)) + 1.0;
  const double beyond =
      count -
      std::pow(std::min(levels_in_range, num_intervals + 1.0), num_actuators);
  if (beyond > kMaxReachChecks) {
    throw InputError(fmt::format(
        "--max: {:.3g} of the {:.3g} configurations lie beyond the "
        "characterised {:.4g} {}, and each needs a reach check (about 1 ms); "
        "keep --max within the characterised range or use a coarser --step "
        "(at most {:.0e} such configurations)",
        beyond, count, max_in_range, pressure_unit, kMaxReachChecks));
  }
  return static_cast<int>(num_intervals);
}

}  // namespace

int RunWorkspace(const WorkspaceCommandOptions& options, std::ostream& out) {
  const ResolvedModel resolved = ResolveModel(options.model);
  RequirePressureUnit(resolved, "--max and --step");
  if (!options.output_path.empty()) {
    CheckOutputFile(options.output_path, "--out");
  }
  const int num_actuators = resolved.mechanism.NumActuators();
  const int num_intervals = CheckedIntervals(
      options, num_actuators, resolved.mpa_per_unit, resolved.pressure_unit,
      resolved.range.max_pressure_mpa / resolved.mpa_per_unit);
  WorkspaceOptions workspace_options;
  workspace_options.num_threads = options.threads;
  // Levels in the user's unit, written back as given (no MPa round trip).
  const std::vector<double> levels =
      EvenPressureLevels(options.max_pressure, num_intervals);
  for (double level : levels) {
    workspace_options.pressure_levels_mpa.push_back(level *
                                                    resolved.mpa_per_unit);
  }
  // Where the model extrapolates: beyond the constants' characterised range.
  workspace_options.range = resolved.range;
  const EquilibriumProblem problem(resolved.mechanism, resolved.force_model);
  const WorkspaceMap map = ComputeWorkspace(problem, workspace_options);

  if (!options.output_path.empty()) {
    PredictionTable table(resolved.mechanism, resolved.pressure_unit);
    const int radix = static_cast<int>(levels.size());
    Eigen::VectorXd pressures(num_actuators);
    for (int i = 0; i < map.pressures_mpa.rows(); ++i) {
      // Row i holds level digits of i in base `radix`, p1 slowest.
      for (int k = num_actuators - 1, rest = i; k >= 0; --k, rest /= radix) {
        pressures[k] = levels[rest % radix];
      }
      table.AddRow(pressures, map.displacements_mm.row(i).transpose(),
                   map.summaries[i], map.in_range[i] != 0,
                   map.within_reach[i] != 0);
    }
    WriteCommandOutput(options.output_path, table.text(), out);
  }
  std::ostream& report = options.output_path == "-" ? std::cerr : out;
  report << fmt::format(
      "{} {}: {} configurations (0 to {} {} in steps of {}), {} converged\n",
      resolved.mechanism.name, resolved.model_name, map.pressures_mpa.rows(),
      options.max_pressure, resolved.pressure_unit, options.step,
      map.pressures_mpa.rows() - map.num_not_converged);
  const std::vector<HeadExtents> extents = map.Extents();
  for (int h = 0; h < resolved.mechanism.NumHeads(); ++h) {
    report << fmt::format(
        "  {}: y {:.4f} .. {:.4f} mm, z {:.4f} .. {:.4f} mm\n",
        resolved.mechanism.heads[h].name, extents[h].min_mm.x(),
        extents[h].max_mm.x(), extents[h].min_mm.y(), extents[h].max_mm.y());
  }
  if (map.num_outside_range > 0) {
    // The first such configuration, for the message.
    const auto first = std::find(map.in_range.begin(), map.in_range.end(), 0);
    const Eigen::Index i = first - map.in_range.begin();
    const std::string first_outside =
        OutsideCharacterisedRange(resolved.range, problem,
                                  map.pressures_mpa.row(i).transpose(),
                                  map.displacements_mm.row(i).transpose())
            .value_or("");
    spdlog::warn(
        "{} configurations lie beyond the range the constants were "
        "characterised over (first: {}): the model extrapolates there, and "
        "the extents include them; rows with in_range = 0",
        map.num_outside_range, first_outside);
  }
  if (map.num_beyond_reach > 0) {
    spdlog::warn(
        "{} configurations put the heads beyond the mechanism's reach (where "
        "no pressures up to the characterised {:.4g} {} hold them): the "
        "extents include them, but the bench cannot show them; rows with "
        "within_reach = 0",
        map.num_beyond_reach,
        resolved.range.max_pressure_mpa / resolved.mpa_per_unit,
        resolved.pressure_unit);
  }
  if (map.num_not_converged > 0) {
    spdlog::warn(
        "{} configurations did not converge; they are excluded from "
        "the extents and written with converged = 0",
        map.num_not_converged);
  }
  return 0;
}

}  // namespace softbench
