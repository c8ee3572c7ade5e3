#include "calibration/constants_file.h"

#include "util/input_error.h"
#include "util/text_file.h"
#include "util/yaml_reader.h"

namespace softbench {

ConstantsFile ParseConstantsYaml(std::string_view yaml,
                                 const std::string& source) {
  const YamlReader reader(source);
  const YAML::Node root = reader.Parse(yaml);
  if (!root.IsMap()) {
    throw InputError(source + ": a constants file is a map of name: value");
  }
  reader.CheckKeys(root,
                   {"axial_area_mm2", "shear_area_factor_mm2_per_rad",
                    "linear_stiffness_n_per_mm", "torsional_factor_n_per_rad",
                    "natural_length_mm", "variant"});
  ConstantsFile file;
  ActuatorConstants& c = file.constants;
  const auto number = [&](std::string_view key) {
    return reader.Number(reader.Require(root, key), key);
  };
  c.axial_area_mm2 = number("axial_area_mm2");
  c.shear_area_factor_mm2_per_rad = number("shear_area_factor_mm2_per_rad");
  c.linear_stiffness_n_per_mm = number("linear_stiffness_n_per_mm");
  c.torsional_factor_n_per_rad = number("torsional_factor_n_per_rad");
  if (root["natural_length_mm"])
    c.natural_length_mm = number("natural_length_mm");
  if (const YAML::Node variant = root["variant"]) {
    file.variant = reader.String(variant, "variant");
    if (!ForceModelFromVariantName(*file.variant, c)) {
      reader.Fail(variant, "variant",
                  "'" + *file.variant +
                      "' is not one of small-angle, full-trig, variable-arm");
    }
  }
  if (const std::optional<std::string> problem = c.Check()) {
    throw InputError(source + ": " + *problem);
  }
  return file;
}

ConstantsFile LoadConstantsFile(const std::string& path) {
  return ParseConstantsYaml(ReadTextFile(path, "constants file"), path);
}

}  // namespace softbench
