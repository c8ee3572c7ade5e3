#ifndef SOFTBENCH_PIPELINES_FORMATS_PRESSURE_CSV_H_
#define SOFTBENCH_PIPELINES_FORMATS_PRESSURE_CSV_H_

#include <Eigen/Core>
#include <string>
#include <vector>

namespace softbench {

// Reads columns p1..pN (in the selected unit) of every row; other columns are
// ignored. Rejects a column count that does not match the mechanism, and
// non-numeric, non-finite or negative pressures, naming file, line and column.
// With `times_s`, also reads column time_s (a pressure log, as the
// regulator's microcontroller records it), which must not decrease.
std::vector<Eigen::VectorXd> ReadPressureRows(const std::string& path,
                                              int num_actuators,
                                              std::vector<double>* times_s);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_FORMATS_PRESSURE_CSV_H_
