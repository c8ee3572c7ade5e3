#include "pipelines/formats/pressure_csv.h"

#include <fmt/format.h>

#include <cmath>

#include "util/csv.h"
#include "util/input_error.h"

namespace softbench {

std::vector<Eigen::VectorXd> ReadPressureRows(const std::string& path,
                                              int num_actuators,
                                              std::vector<double>* times_s) {
  CsvReader reader(path);
  std::vector<int> columns;
  for (int a = 1; a <= num_actuators; ++a) {
    const int column = reader.ColumnIndex(fmt::format("p{}", a));
    if (column < 0) {
      throw InputError(fmt::format(
          "{}:1: column p{} is missing; the mechanism has {} actuators, so "
          "give columns p1..p{}",
          path, a, num_actuators, num_actuators));
    }
    columns.push_back(column);
  }
  if (reader.ColumnIndex(fmt::format("p{}", num_actuators + 1)) >= 0) {
    throw InputError(fmt::format(
        "{}:1: column p{} is one too many; the mechanism has {} actuators",
        path, num_actuators + 1, num_actuators));
  }
  const int time_column = reader.ColumnIndex("time_s");
  if (times_s != nullptr && time_column < 0) {
    throw InputError(path +
                     ":1: column time_s is missing; a pressure log "
                     "has columns time_s,p1..pN");
  }
  std::vector<Eigen::VectorXd> rows;
  std::vector<std::string_view> fields;
  while (reader.ReadRow(&fields)) {
    if (times_s != nullptr) {
      const std::optional<double> t = ParseDouble(fields[time_column]);
      if (!t || !std::isfinite(*t)) {
        throw InputError(fmt::format("{}time_s: '{}' is not a number",
                                     reader.Where(), fields[time_column]));
      }
      if (!times_s->empty() && *t < times_s->back()) {
        throw InputError(fmt::format(
            "{}time_s {} is before the previous row's {}; sort the log by "
            "time",
            reader.Where(), *t, times_s->back()));
      }
      times_s->push_back(*t);
    }
    Eigen::VectorXd pressures(num_actuators);
    for (int a = 0; a < num_actuators; ++a) {
      const std::string_view field = fields[columns[a]];
      const std::optional<double> value = ParseDouble(field);
      if (!value || !std::isfinite(*value)) {
        throw InputError(fmt::format("{}column p{}: '{}' is not a number",
                                     reader.Where(), a + 1, field));
      }
      if (*value < 0.0) {
        throw InputError(fmt::format(
            "{}column p{}: {} is negative; pressures are gauge pressures >= 0",
            reader.Where(), a + 1, *value));
      }
      pressures[a] = *value;
    }
    rows.push_back(pressures);
  }
  if (rows.empty()) {
    throw InputError(path + ": no pressure rows; add at least one row");
  }
  return rows;
}

}  // namespace softbench
