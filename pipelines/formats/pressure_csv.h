#ifndef SOFTBENCH_PIPELINES_FORMATS_PRESSURE_CSV_H_
#define SOFTBENCH_PIPELINES_FORMATS_PRESSURE_CSV_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "util/csv.h"

namespace softbench {

// What a pressure CSV is read against.
struct PressureCsvOptions {
  int num_actuators = 0;    // columns p1..pN, one per actuator
  bool with_times = false;  // also column time_s (a regulator's log)
  // The unit stated outside the file (the plan's pressure_unit, the
  // --pressure-unit flag), or none; rows are returned in it.
  std::optional<std::string> stated_unit;
  // How a user states the unit outside the file, for the message when
  // neither the file nor the caller does ("or pass --pressure-unit").
  std::string how_to_state;
  // The numbers' decimal mark, as the user declared it (--decimal-comma).
  DecimalMark decimal_mark = DecimalMark::kPoint;
};

// Pressures read from a CSV, in one stated unit.
struct PressureRows {
  std::vector<Eigen::VectorXd> rows;  // one per data row, in `unit`
  std::vector<double> times_s;        // column time_s, with_times only
  std::string unit;                   // a name of kPressureUnits
  double mpa_per_unit = 0.0;          // MPa per `unit`
};

// Reads columns p1..pN of every row; other columns are ignored. A column
// states its unit in its name (p1_psi, p1_kpa, p1_mpa; all columns alike),
// or the caller states it; a pressure whose unit nobody states is an error,
// never taken as kPa. Rejects a column count that does not match the
// mechanism, and non-numeric, non-finite or negative pressures, naming file,
// line and column. time_s must not decrease.
PressureRows ReadPressureRows(const std::string& path,
                              const PressureCsvOptions& options);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_FORMATS_PRESSURE_CSV_H_
