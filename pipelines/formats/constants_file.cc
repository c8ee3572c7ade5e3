#include "pipelines/formats/constants_file.h"

#include <fmt/format.h>

#include "model/units.h"
#include "util/input_error.h"
#include "util/text_file.h"
#include "util/yaml_reader.h"

namespace softbench {

// Five constants and comments.
constexpr int64_t kMaxConstantsBytes = int64_t{64} << 10;

ConstantsFile ParseConstantsYaml(std::string_view yaml,
                                 const std::string& source) {
  const YamlReader reader(source);
  const YAML::Node root = reader.Parse(yaml);
  if (!root.IsMap()) {
    throw InputError(source + ": a constants file is a map of name: value");
  }
  reader.CheckKeys(
      root, "constants file",
      {"axial_area_mm2", "shear_area_factor_mm2_per_rad",
       "linear_stiffness_n_per_mm", "torsional_factor_n_per_rad",
       "natural_length_mm", "variant", "characterised_max_pressure_mpa",
       "characterised_max_delta_length_mm", "characterised_max_theta_deg"});
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
      reader.Fail(
          variant, "variant",
          "'" + *file.variant + "' is not one of " + ModelVariantNames());
    }
  }
  if (const std::optional<std::string> problem = c.Problem()) {
    throw InputError(source + ": " + *problem);
  }
  const auto limit = [&](std::string_view key, double* value) {
    if (const YAML::Node node = root[std::string(key)]) {
      *value = reader.Number(node, key);
      if (!(*value > 0.0)) reader.Fail(node, key, "must be > 0");
    }
  };
  limit("characterised_max_pressure_mpa", &file.range.max_pressure_mpa);
  limit("characterised_max_delta_length_mm",
        &file.range.max_abs_delta_length_mm);
  double max_theta_deg = RadToDeg(file.range.max_abs_theta_rad);
  limit("characterised_max_theta_deg", &max_theta_deg);
  file.range.max_abs_theta_rad = DegToRad(max_theta_deg);
  return file;
}

ConstantsFile LoadConstantsFile(const std::string& path) {
  return ParseConstantsYaml(
      ReadTextFile(path, "constants file", kMaxConstantsBytes), path);
}

std::string ConstantsYaml(const ConstantsFile& file, std::string_view comment) {
  const ActuatorConstants& c = file.constants;
  std::string out(comment);
  // 17 significant digits: the file reads back to the same doubles.
  out += fmt::format("axial_area_mm2: {:.17g}  # A_z\n", c.axial_area_mm2);
  out += fmt::format("shear_area_factor_mm2_per_rad: {:.17g}  # W_y\n",
                     c.shear_area_factor_mm2_per_rad);
  out += fmt::format("linear_stiffness_n_per_mm: {:.17g}  # k_s\n",
                     c.linear_stiffness_n_per_mm);
  out += fmt::format("torsional_factor_n_per_rad: {:.17g}  # k_theta\n",
                     c.torsional_factor_n_per_rad);
  out += fmt::format("natural_length_mm: {:.17g}  # L0 (not fitted)\n",
                     c.natural_length_mm);
  if (file.variant) out += fmt::format("variant: {}\n", *file.variant);
  const CharacterisedRange& r = file.range;
  out += "# The range fitted over: predictions beyond it are marked.\n";
  out += fmt::format("characterised_max_pressure_mpa: {:.17g}\n",
                     r.max_pressure_mpa);
  out += fmt::format("characterised_max_delta_length_mm: {:.17g}\n",
                     r.max_abs_delta_length_mm);
  out += fmt::format("characterised_max_theta_deg: {:.17g}\n",
                     RadToDeg(r.max_abs_theta_rad));
  return out;
}

}  // namespace softbench
