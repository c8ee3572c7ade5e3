#include "pipelines/commands/model_flags.h"

#include <fmt/format.h>

#include <cmath>

#include "model/units.h"
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
                      ModelVariantNames() +
                          " (axial-shear only; default: the constants "
                          "file's, else small-angle)");
  command->add_option("--constants", selection->constants_path,
                      "actuator constants YAML (default: the thesis's fit)");
  command->add_option(
      "--pressure-unit", selection->pressure_unit,
      "unit of pressures read and written: " + PressureUnitNames() +
          " (required unless an input's columns state it)");
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
