#ifndef SOFTBENCH_PIPELINES_SYNTHETIC_FORCE_LOGS_H_
#define SOFTBENCH_PIPELINES_SYNTHETIC_FORCE_LOGS_H_

#include <cstdint>
#include <optional>
#include <string>

#include "calibration/synthetic_force_log.h"

namespace softbench {

// The thesis's 54-test characterisation protocol written as force-sensor
// logs from known constants (docs/file-formats.md#force-logs): one CSV per
// test and a manifest, or one combined CSV and its manifest.
struct ForceLogFilesOptions {
  // The protocol, the true model and the rig's imperfections.
  SyntheticForceLogOptions synthetic;
  // The unit of the pressure column: a name of kPressureUnits.
  std::string pressure_unit = "kpa";
  // The true model's name, for the manifest's comment ("small-angle").
  std::string model_name = "small-angle";
  bool combined = false;  // one CSV with configuration columns
  int threads = 0;        // files written at once (0: one per core)
  bool progress = true;   // report progress (util/progress.h)

  // The first bad field, named, and what it must be.
  std::optional<std::string> Problem() const;
};

struct ForceLogFiles {
  int tests = 0;
  int64_t rows = 0;
  std::string manifest_path;
};

// What WriteForceLogFiles will write: the rows exactly, the bytes
// estimated from the first test's formatted rows (within a few per cent),
// so a caller can state the size, and check the disk, before writing.
struct ForceLogFilesSize {
  int tests = 0;
  int64_t rows = 0;
  int64_t bytes = 0;
};
ForceLogFilesSize EstimateForceLogFiles(const ForceLogFilesOptions& options);

// Writes the logs and manifest.yaml into `directory` (created), each file
// atomically. Throws InputError when the directory cannot be written.
ForceLogFiles WriteForceLogFiles(const std::string& directory,
                                 const ForceLogFilesOptions& options);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_SYNTHETIC_FORCE_LOGS_H_
