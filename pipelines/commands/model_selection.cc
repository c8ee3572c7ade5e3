#include "pipelines/commands/model_selection.h"

#include <fmt/format.h>

#include "model/units.h"
#include "pipelines/formats/constants_file.h"
#include "pipelines/formats/mechanism_io.h"
#include "util/input_error.h"

namespace softbench {

double MpaPerPressureUnitFlag(const std::string& unit) {
  if (const std::optional<double> mpa = MpaPerPressureUnit(unit)) return *mpa;
  throw InputError("--pressure-unit: '" + unit + "' is not a unit; use " +
                   PressureUnitNames());
}

void RequirePressureUnit(const ResolvedModel& resolved, std::string_view what) {
  if (resolved.pressure_unit.empty()) {
    throw InputError(fmt::format(
        "--pressure-unit: missing; say which unit {} in: {} (softbench "
        "never assumes one)",
        fmt::format(
            "{} {}", what,
            what.find(" and ") == std::string_view::npos ? "is" : "are"),
        PressureUnitNames()));
  }
}

ResolvedModel ResolveModel(const ModelSelection& selection) {
  ResolvedModel resolved;
  if (selection.pressure_unit) {
    resolved.mpa_per_unit = MpaPerPressureUnitFlag(*selection.pressure_unit);
    resolved.pressure_unit = FindPressureUnit(*selection.pressure_unit)->name;
  }
  resolved.mechanism = LoadMechanism(selection.mechanism);
  if (!selection.constants_path.empty()) {
    resolved.range = LoadConstantsFile(selection.constants_path).range;
  }

  if (selection.model == "pressurized-spring") {
    if (selection.variant) {
      throw InputError(
          "--variant: applies to the axial-shear model only; the "
          "pressurized-spring baseline has no variants");
    }
    const ActuatorConstants constants =
        selection.constants_path.empty()
            ? ActuatorConstants()
            : LoadConstantsFile(selection.constants_path).constants;
    resolved.force_model = ForceModel::PressurizedSpring(constants);
    resolved.model_name = "pressurized-spring";
    return resolved;
  }
  if (selection.model != "axial-shear") {
    throw InputError("--model: '" + selection.model +
                     "' is not a model; use axial-shear or pressurized-spring");
  }
  std::string variant;
  resolved.force_model = ResolveAxialShearModel(selection.constants_path,
                                                selection.variant, &variant);
  resolved.model_name = "axial-shear (" + variant + ")";
  return resolved;
}

ForceModel ResolveAxialShearModel(const std::string& constants_path,
                                  const std::optional<std::string>& variant,
                                  std::string* variant_used) {
  ConstantsFile constants;
  if (!constants_path.empty()) constants = LoadConstantsFile(constants_path);
  const std::string name = variant             ? *variant
                           : constants.variant ? *constants.variant
                                               : "small-angle";
  const std::optional<ForceModel> model =
      ForceModelFromVariantName(name, constants.constants);
  if (!model) {
    throw InputError("--variant: '" + name + "' is not a variant; use " +
                     ModelVariantNames());
  }
  if (variant_used != nullptr) *variant_used = name;
  return *model;
}

}  // namespace softbench
