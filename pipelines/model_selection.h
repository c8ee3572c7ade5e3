#ifndef SOFTBENCH_PIPELINES_MODEL_SELECTION_H_
#define SOFTBENCH_PIPELINES_MODEL_SELECTION_H_

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <string>
#include <vector>

#include "model/actuator_model.h"
#include "model/mechanism.h"

namespace softbench {

// What every model command is asked to use: the mechanism, the force model,
// its constants and the pressure unit of inputs and outputs.
struct ModelSelection {
  std::string mechanism = "delta";    // "delta", "floating" or a YAML path
  std::string model = "axial-shear";  // or "pressurized-spring"
  std::string variant;         // empty: the constants file's, else small-angle
  std::string constants_path;  // empty: the thesis's constants
  std::string pressure_unit = "kpa";  // psi, kpa or mpa
};

// The selection, loaded and checked.
struct ResolvedModel {
  Mechanism mechanism;
  ForceModel force_model;
  std::string model_name;  // "axial-shear (small-angle)", "pressurized-spring"
  std::string pressure_unit;  // as given
  double mpa_per_unit = 1.0;  // multiply a pressure in `pressure_unit` by this
};

// Adds --mechanism, --model, --variant, --constants and --pressure-unit.
void AddModelSelectionOptions(CLI::App* command, ModelSelection* selection);

// Loads the mechanism and constants; throws InputError on any bad choice.
ResolvedModel ResolveModel(const ModelSelection& selection);

// The axial-shear model of `variant` (empty: the constants file's, else
// small-angle) with the constants of `constants_path` (empty: the thesis's);
// throws InputError. `variant_used` (optional) receives the variant's name.
ForceModel ResolveAxialShearModel(const std::string& constants_path,
                                  const std::string& variant,
                                  std::string* variant_used);

// MPa per unit for "psi", "kpa" or "mpa"; throws InputError otherwise.
double MpaPerPressureUnit(const std::string& unit);

// Parses "a,b,c" into numbers; throws InputError naming `option` and the
// offending item.
std::vector<double> ParseNumberList(const std::string& text,
                                    const std::string& option);

// Formats head displacements "head: y = ... mm, z = ... mm; ..." for people.
std::string FormatHeadPositions(const Mechanism& mechanism,
                                const Eigen::VectorXd& displacements_mm);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_MODEL_SELECTION_H_
