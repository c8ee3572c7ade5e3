#include "pipelines/formats/pressure_csv.h"

#include <fmt/format.h>

#include <cmath>

#include "model/units.h"
#include "util/csv.h"
#include "util/input_error.h"

namespace softbench {
namespace {

// The pressure columns' indices and the unit their names state ("" when
// they are plain p1..pN).
struct PressureColumns {
  std::vector<int> indices;
  std::string unit;
};

// Column pA of `reader`'s header, plain ("p2") or with a unit suffix in any
// case ("p2_psi", "p2_kPa"; `unit` gets the unit's name, "" when plain); -1
// if absent. A suffix that is not a unit is an error naming it.
int FindPressureColumn(const CsvReader& reader, int a, std::string* unit) {
  const std::string plain = fmt::format("p{}", a);
  const std::vector<std::string>& header = reader.header();
  for (size_t i = 0; i < header.size(); ++i) {
    const std::string& name = header[i];
    if (name == plain) {
      *unit = "";
      return static_cast<int>(i);
    }
    if (!name.starts_with(plain + "_")) continue;
    const std::string_view suffix =
        static_cast<std::string_view>(name).substr(plain.size() + 1);
    const PressureUnit* found = FindPressureUnit(suffix);
    if (found == nullptr) {
      throw InputError(fmt::format(
          "{}:1: column '{}': '{}' is not a pressure unit; use {} (e.g. "
          "{}_psi)",
          reader.path(), name, suffix, PressureUnitNames(), plain));
    }
    *unit = found->name;
    return static_cast<int>(i);
  }
  return -1;
}

PressureColumns FindPressureColumns(const CsvReader& reader, int n) {
  const std::string& path = reader.path();
  PressureColumns columns;
  for (int a = 1; a <= n; ++a) {
    std::string unit;
    const int column = FindPressureColumn(reader, a, &unit);
    if (column < 0) {
      throw InputError(fmt::format(
          "{}:1: column p{} is missing; the mechanism has {} actuators, so "
          "give columns p1..p{} (with their unit, e.g. p1_psi)",
          path, a, n, n));
    }
    if (a > 1 && unit != columns.unit) {
      throw InputError(fmt::format(
          "{}:1: column p{} is in '{}' but p1 in '{}'; give every pressure "
          "column the same unit",
          path, a, unit, columns.unit));
    }
    columns.unit = unit;
    columns.indices.push_back(column);
  }
  std::string unit;
  if (FindPressureColumn(reader, n + 1, &unit) >= 0) {
    throw InputError(fmt::format(
        "{}:1: column p{} is one too many; the mechanism has {} actuators",
        path, n + 1, n));
  }
  return columns;
}

double ReadPressure(const CsvReader& reader, std::string_view field, int a,
                    double mpa_per_unit, std::string_view unit) {
  const std::optional<double> value = ParseDouble(field);
  if (!value || !std::isfinite(*value)) {
    throw InputError(fmt::format("{}column p{}: '{}' is not a number",
                                 reader.Where(), a, field));
  }
  if (const std::optional<std::string> why =
          ImplausiblePressure(*value, mpa_per_unit, unit)) {
    throw InputError(fmt::format("{}column p{}: {}", reader.Where(), a, *why));
  }
  return *value;
}

}  // namespace

PressureRows ReadPressureRows(const std::string& path,
                              const PressureCsvOptions& options) {
  CsvReader reader(path, options.decimal_mark);
  const PressureColumns columns =
      FindPressureColumns(reader, options.num_actuators);
  if (columns.unit.empty() && !options.stated_unit) {
    throw InputError(fmt::format(
        "{}:1: the pressure columns do not say their unit; name them "
        "p1_psi, p1_kpa or p1_mpa ...{}",
        path, options.how_to_state.empty() ? "" : ", " + options.how_to_state));
  }
  PressureRows result;
  result.unit = options.stated_unit.value_or(columns.unit);
  const std::optional<double> mpa_per_unit = MpaPerPressureUnit(result.unit);
  const std::optional<double> file_mpa_per_unit =
      MpaPerPressureUnit(columns.unit.empty() ? result.unit : columns.unit);
  if (!mpa_per_unit || !file_mpa_per_unit) {
    throw InputError(fmt::format("{}: '{}' is not a pressure unit; use {}",
                                 path, result.unit, PressureUnitNames()));
  }
  result.mpa_per_unit = *mpa_per_unit;
  const double to_unit = *file_mpa_per_unit / *mpa_per_unit;
  const std::string_view file_unit =
      columns.unit.empty() ? result.unit : columns.unit;
  const int time_column = reader.ColumnIndex("time_s");
  if (options.with_times && time_column < 0) {
    throw InputError(path +
                     ":1: column time_s is missing; a pressure log "
                     "has columns time_s,p1_UNIT..pN_UNIT");
  }
  std::vector<std::string_view> fields;
  while (reader.ReadRow(&fields)) {
    if (options.with_times) {
      const std::optional<double> t = ParseDouble(fields[time_column]);
      if (!t || !std::isfinite(*t)) {
        throw InputError(fmt::format("{}time_s: '{}' is not a number",
                                     reader.Where(), fields[time_column]));
      }
      if (!result.times_s.empty() && *t < result.times_s.back()) {
        throw InputError(fmt::format(
            "{}time_s {} is before the previous row's {}; sort the log by "
            "time",
            reader.Where(), *t, result.times_s.back()));
      }
      result.times_s.push_back(*t);
    }
    Eigen::VectorXd pressures(options.num_actuators);
    for (int a = 0; a < options.num_actuators; ++a) {
      pressures[a] = ReadPressure(reader, fields[columns.indices[a]], a + 1,
                                  *file_mpa_per_unit, file_unit) *
                     to_unit;
    }
    result.rows.push_back(pressures);
  }
  if (result.rows.empty()) {
    throw InputError(path + ": no pressure rows; add at least one row");
  }
  return result;
}

}  // namespace softbench
