#include "pipelines/model_selection.h"

#include <fmt/format.h>

#include "calibration/constants_file.h"
#include "model/units.h"
#include "pipelines/mechanism_io.h"
#include "util/csv.h"
#include "util/input_error.h"

namespace softbench {

void AddModelSelectionOptions(CLI::App* command, ModelSelection* selection) {
  command
      ->add_option("--mechanism", selection->mechanism,
                   "delta, floating, or a mechanism YAML file")
      ->capture_default_str();
  command
      ->add_option("--model", selection->model,
                   "axial-shear (the thesis's model) or pressurized-spring "
                   "(the baseline of [26])")
      ->capture_default_str();
  command->add_option("--variant", selection->variant,
                      "small-angle, full-trig or variable-arm (axial-shear "
                      "only; default: the constants file's, else small-angle)");
  command->add_option("--constants", selection->constants_path,
                      "actuator constants YAML (default: the thesis's fit)");
  command
      ->add_option("--pressure-unit", selection->pressure_unit,
                   "unit of pressures read and written: psi, kpa or mpa")
      ->capture_default_str();
}

double MpaPerPressureUnit(const std::string& unit) {
  if (unit == "psi") return kMpaPerPsi;
  if (unit == "kpa") return kMpaPerKpa;
  if (unit == "mpa") return 1.0;
  throw InputError("--pressure-unit: '" + unit +
                   "' is not a unit; use psi, kpa or mpa");
}

ResolvedModel ResolveModel(const ModelSelection& selection) {
  ResolvedModel resolved;
  resolved.mpa_per_unit = MpaPerPressureUnit(selection.pressure_unit);
  resolved.pressure_unit = selection.pressure_unit;
  resolved.mechanism = LoadMechanism(selection.mechanism);

  if (selection.model == "pressurized-spring") {
    if (!selection.variant.empty()) {
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
                                  const std::string& variant,
                                  std::string* variant_used) {
  ConstantsFile constants;
  if (!constants_path.empty()) constants = LoadConstantsFile(constants_path);
  const std::string name = !variant.empty()    ? variant
                           : constants.variant ? *constants.variant
                                               : "small-angle";
  const std::optional<ForceModel> model =
      ForceModelFromVariantName(name, constants.constants);
  if (!model) {
    throw InputError("--variant: '" + name +
                     "' is not a variant; use small-angle, full-trig or "
                     "variable-arm");
  }
  if (variant_used != nullptr) *variant_used = name;
  return *model;
}

std::vector<double> ParseNumberList(const std::string& text,
                                    const std::string& option) {
  std::vector<std::string_view> items;
  SplitCsvLine(text, &items);
  std::vector<double> numbers;
  for (std::string_view item : items) {
    const std::optional<double> value = ParseDouble(item);
    if (!value || !std::isfinite(*value)) {
      throw InputError(option + ": '" + std::string(item) +
                       "' is not a number; give comma-separated numbers");
    }
    numbers.push_back(*value);
  }
  return numbers;
}

std::string FormatHeadPositions(const Mechanism& mechanism,
                                const Eigen::VectorXd& displacements_mm) {
  std::string text;
  for (int h = 0; h < mechanism.NumHeads(); ++h) {
    text += fmt::format("{}{}: y = {:.4f} mm, z = {:.4f} mm",
                        h == 0 ? "" : "; ", mechanism.heads[h].name,
                        displacements_mm[2 * h], displacements_mm[2 * h + 1]);
  }
  return text;
}

}  // namespace softbench
