#include "pipelines/characterisation/force_log_manifest.h"

#include <fmt/format.h>

#include <filesystem>

#include "model/units.h"
#include "util/input_error.h"
#include "util/text_file.h"
#include "util/yaml_reader.h"

namespace softbench {

// A manifest lists log files; thousands of entries fit in far less.
constexpr int64_t kMaxManifestBytes = int64_t{4} << 20;

void ParseSignedColumn(const std::string& text, const std::string& what,
                       std::string* column, double* sign) {
  std::string_view name = text;
  *sign = 1.0;
  if (!name.empty() && (name.front() == '+' || name.front() == '-')) {
    *sign = name.front() == '-' ? -1.0 : 1.0;
    name.remove_prefix(1);
  }
  if (name.empty()) {
    throw InputError(what +
                     ": give a column name, optionally signed: "
                     "'+fz_n' or '-fy_n'");
  }
  *column = name;
}

namespace {

// The pressure unit, the column names and the sensor axes' signs.
ForceLogColumns ParseColumns(const YamlReader& reader, const YAML::Node& root) {
  ForceLogColumns columns;
  const YAML::Node unit_node = reader.Require(root, "pressure_unit");
  const std::string unit = reader.String(unit_node, "pressure_unit");
  if (const std::optional<double> mpa = MpaPerPressureUnit(unit)) {
    columns.mpa_per_unit = *mpa;
  } else {
    reader.Fail(unit_node, "pressure_unit",
                "'" + unit + "' is not a unit; use " + PressureUnitNames());
  }
  columns.pressure = "pressure_" + unit;
  if (const YAML::Node names = root["columns"]) {
    reader.CheckKeys(names, "columns", {"time", "pressure"});
    if (names["time"]) columns.time = reader.String(names["time"], "time");
    if (names["pressure"]) {
      columns.pressure = reader.String(names["pressure"], "pressure");
      // A column whose name states a unit (pressure_kpa) must state this
      // one: read in another, every pressure is off by a constant factor.
      const size_t underscore = columns.pressure.rfind('_');
      const PressureUnit* named =
          underscore == std::string::npos
              ? nullptr
              : FindPressureUnit(static_cast<std::string_view>(columns.pressure)
                                     .substr(underscore + 1));
      if (named != nullptr &&
          *MpaPerPressureUnit(unit) != named->mpa_per_unit) {
        reader.Fail(
            unit_node, "pressure_unit",
            fmt::format("is {}, but the pressure column '{}' is in "
                        "{}; set pressure_unit: {}, or name the "
                        "column for the unit its numbers are in",
                        unit, columns.pressure, named->name, named->name));
      }
    }
  }
  if (const YAML::Node axes = root["axes"]) {
    reader.CheckKeys(axes, "axes", {"axial", "shear"});
    if (axes["axial"]) {
      ParseSignedColumn(reader.String(axes["axial"], "axial"),
                        reader.Where(axes["axial"]) + "axes.axial",
                        &columns.axial, &columns.axial_sign);
    }
    if (axes["shear"]) {
      ParseSignedColumn(reader.String(axes["shear"], "shear"),
                        reader.Where(axes["shear"]) + "axes.shear",
                        &columns.shear, &columns.shear_sign);
    }
  }
  return columns;
}

// One test entry; its id must differ from the earlier `tests`'.
ForceTest ParseTest(const YamlReader& reader, const YAML::Node& node,
                    const std::vector<ForceTest>& earlier) {
  ForceTest test;
  reader.CheckKeys(node, "tests entry",
                   {"id", "file", "delta_length_mm", "theta_deg",
                    "measured_delta_length_mm", "measured_theta_deg"});
  test.id = reader.String(reader.Require(node, "id"), "id");
  for (const ForceTest& other : earlier) {
    if (other.id == test.id) {
      reader.Fail(node["id"], "id", "'" + test.id + "' is used twice");
    }
  }
  test.nominal_delta_length_mm =
      reader.Number(reader.Require(node, "delta_length_mm"), "delta_length_mm");
  test.nominal_theta_rad =
      DegToRad(reader.Number(reader.Require(node, "theta_deg"), "theta_deg"));
  if (node["measured_delta_length_mm"]) {
    test.measured_delta_length_mm = reader.Number(
        node["measured_delta_length_mm"], "measured_delta_length_mm");
  }
  if (node["measured_theta_deg"]) {
    test.measured_theta_rad = DegToRad(
        reader.Number(node["measured_theta_deg"], "measured_theta_deg"));
  }
  if (const auto problem = ImplausibleTest(test)) {
    reader.Fail(node, "tests entry '" + test.id + "'", *problem);
  }
  return test;
}

}  // namespace

ForceLogManifest ParseForceLogManifest(std::string_view yaml,
                                       const std::string& source,
                                       const std::string& base_directory) {
  const YamlReader reader(source);
  const YAML::Node root = reader.Parse(yaml);
  if (!root.IsMap()) {
    throw InputError(source +
                     ": a force-log manifest is a map (see "
                     "docs/file-formats.md#force-logs)");
  }
  reader.CheckKeys(root, "force-log manifest",
                   {"pressure_unit", "columns", "axes", "tests", "combined"});
  ForceLogManifest manifest;
  manifest.columns = ParseColumns(reader, root);
  const auto resolve = [&](const std::string& file) {
    const std::filesystem::path path(file);
    return path.is_absolute() ? file : (base_directory / path).string();
  };
  const YAML::Node tests = root["tests"];
  const YAML::Node combined = root["combined"];
  if (static_cast<bool>(tests) == static_cast<bool>(combined)) {
    throw InputError(source +
                     ": give either 'tests' (one CSV per test) or 'combined' "
                     "(one CSV with configuration columns)");
  }
  if (combined) {
    manifest.combined_path = resolve(reader.String(combined, "combined"));
    return manifest;
  }
  if (!tests.IsSequence() || tests.size() == 0) {
    reader.Fail(tests, "tests", "must be a non-empty list of tests");
  }
  for (const YAML::Node& node : tests) {
    manifest.tests.push_back(ParseTest(reader, node, manifest.tests));
    manifest.files.push_back(
        resolve(reader.String(reader.Require(node, "file"), "file")));
  }
  return manifest;
}

ForceLogManifest LoadForceLogManifest(const std::string& path) {
  return ParseForceLogManifest(
      ReadTextFile(path, "force-log manifest", kMaxManifestBytes), path,
      std::filesystem::path(path).parent_path().string());
}

std::string ForceLogManifestYaml(const ForceLogManifest& manifest,
                                 const std::string& pressure_unit,
                                 const std::string& comment) {
  const ForceLogColumns& c = manifest.columns;
  std::string out = comment;
  out += fmt::format("pressure_unit: {}\n", pressure_unit);
  out +=
      fmt::format("columns: {{time: {}, pressure: {}}}\n", c.time, c.pressure);
  out += fmt::format("axes: {{axial: \"{}{}\", shear: \"{}{}\"}}\n",
                     c.axial_sign < 0 ? '-' : '+', c.axial,
                     c.shear_sign < 0 ? '-' : '+', c.shear);
  if (!manifest.combined_path.empty()) {
    return out + fmt::format("combined: {}\n", manifest.combined_path);
  }
  out += "tests:\n";
  for (size_t i = 0; i < manifest.tests.size(); ++i) {
    const ForceTest& test = manifest.tests[i];
    out += fmt::format(
        "  - {{id: {}, file: {}, delta_length_mm: {:.6g}, theta_deg: {:.6g}",
        test.id, manifest.files[i], test.nominal_delta_length_mm,
        RadToDeg(test.nominal_theta_rad));
    if (test.measured_delta_length_mm) {
      out += fmt::format(", measured_delta_length_mm: {:.4f}",
                         *test.measured_delta_length_mm);
    }
    if (test.measured_theta_rad) {
      out += fmt::format(", measured_theta_deg: {:.4f}",
                         RadToDeg(*test.measured_theta_rad));
    }
    out += "}\n";
  }
  return out;
}

}  // namespace softbench
