#ifndef SOFTBENCH_CALIBRATION_FORCE_LOG_READER_H_
#define SOFTBENCH_CALIBRATION_FORCE_LOG_READER_H_

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "calibration/force_test.h"
#include "util/csv.h"

namespace softbench {

// Which columns of a force-sensor log hold what, and how the sensor's axes
// map onto the actuator's local axes (model.md, "One actuator").
struct ForceLogColumns {
  std::string time = "time_s";
  std::string pressure = "pressure_kpa";
  // Multiply a pressure in the log's unit by this to get MPa.
  double mpa_per_unit = 0.001;
  // The sensor column along the actuator's local +z (axial) and +y (shear),
  // and the sign that turns the sensor's reading into the force the actuator
  // exerts on its head.
  std::string axial = "fz_n";
  double axial_sign = 1.0;
  std::string shear = "fy_n";
  double shear_sign = 1.0;
};

struct ForceLogReadOptions {
  ForceBinningOptions binning;
  // Rows with |force| above this are out of range and skipped: the Mini40's
  // calibrated axial range is +-120 N (thesis 3.1.2); twice that is no
  // reading.
  double max_abs_force_n = 240.0;
  // Rows with pressure outside this range [MPa] are skipped: the regulator
  // delivers 0-69 kPa, the pressure sensor reads to 103 kPa (thesis 3.2).
  double min_pressure_mpa = -0.01;
  double max_pressure_mpa = 0.2;
  // More skipped rows than this fraction of a file is an error, not noise.
  double max_skipped_fraction = 0.01;
  // Keep every n-th valid row in memory for the row-wise (robust) fit; 0
  // keeps none, which keeps memory independent of the log's length.
  int64_t keep_every_nth_row = 0;
  // The numbers' decimal mark, as the user declared it (--decimal-comma).
  DecimalMark decimal_mark = DecimalMark::kPoint;

  std::optional<std::string> Problem() const;
};

// A row kept for the row-wise fit.
struct ForceRow {
  double pressure_mpa = 0.0;
  double axial_n = 0.0;
  double shear_n = 0.0;
  int test = 0;  // index into the test list
};

// What reading found besides the statistics.
struct ForceLogReadSummary {
  int64_t rows = 0;          // valid rows used
  int64_t rows_skipped = 0;  // NaN/inf, unparsable or out of range
  // The first few skipped rows, "file:line: why".
  std::vector<std::string> skipped_examples;

  void Merge(const ForceLogReadSummary& other);
};

// Streams one test's CSV (time, pressure, forces, ... in any column order)
// into `test->statistics`. Throws InputError for a missing column, a row
// with the wrong number of fields, time going backwards, no zero-pressure
// rows, or too many skipped rows. `test_index` tags kept rows; `bytes_done`
// (optional) counts bytes read, for a progress bar on another thread.
void ReadForceTestCsv(const std::string& path, const ForceLogColumns& columns,
                      const ForceLogReadOptions& options, int test_index,
                      ForceTest* test, ForceLogReadSummary* summary,
                      std::vector<ForceRow>* kept_rows,
                      std::atomic<int64_t>* bytes_done);

// Streams a combined log: the columns of a test CSV plus `test_id`,
// `delta_length_mm`, `theta_deg` and optionally `measured_delta_length_mm`,
// `measured_theta_deg`, with each test's rows contiguous. Tests are returned
// in the order they first appear.
std::vector<ForceTest> ReadCombinedForceLog(const std::string& path,
                                            const ForceLogColumns& columns,
                                            const ForceLogReadOptions& options,
                                            ForceLogReadSummary* summary,
                                            std::vector<ForceRow>* kept_rows,
                                            std::atomic<int64_t>* bytes_done);

}  // namespace softbench

#endif  // SOFTBENCH_CALIBRATION_FORCE_LOG_READER_H_
