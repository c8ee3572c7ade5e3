#ifndef SOFTBENCH_PIPELINES_COMMANDS_MODEL_SELECTION_H_
#define SOFTBENCH_PIPELINES_COMMANDS_MODEL_SELECTION_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "model/actuator_model.h"
#include "model/characterised_range.h"
#include "model/mechanism.h"

namespace softbench {

// What every model command is asked to use: the mechanism, the force model,
// its constants and the pressure unit of inputs and outputs.
struct ModelSelection {
  std::string mechanism = "delta";    // "delta", "floating" or a YAML path
  std::string model = "axial-shear";  // or "pressurized-spring"
  // Unset: the constants file's, else small-angle; set, even to "", it
  // must name a variant.
  std::optional<std::string> variant;
  std::string constants_path;  // empty: the thesis's constants
  // A name of kPressureUnits; never defaulted: a pressure without a stated
  // unit is an error.
  std::optional<std::string> pressure_unit;
};

// The selection, loaded and checked.
struct ResolvedModel {
  Mechanism mechanism;
  ForceModel force_model;
  std::string model_name;  // "axial-shear (small-angle)", "pressurized-spring"
  std::string pressure_unit;  // as given; empty when not given
  double mpa_per_unit = 0.0;  // multiply a pressure in `pressure_unit` by this
  // Where the constants hold (their file's, else the thesis's protocol).
  CharacterisedRange range;
};

// Throws unless --pressure-unit was given; `what` names the pressures that
// need it ("--pressures").
void RequirePressureUnit(const ResolvedModel& resolved, std::string_view what);

// Loads the mechanism and constants; throws InputError on any bad choice.
ResolvedModel ResolveModel(const ModelSelection& selection);

// The axial-shear model of `variant` (empty: the constants file's, else
// small-angle) with the constants of `constants_path` (empty: the thesis's);
// throws InputError. `variant_used` (optional) receives the variant's name.
ForceModel ResolveAxialShearModel(const std::string& constants_path,
                                  const std::optional<std::string>& variant,
                                  std::string* variant_used);

// MPa per unit of --pressure-unit; throws InputError naming the flag.
double MpaPerPressureUnitFlag(const std::string& unit);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_COMMANDS_MODEL_SELECTION_H_
