#ifndef SOFTBENCH_PIPELINES_CHARACTERISATION_FORCE_LOG_MANIFEST_H_
#define SOFTBENCH_PIPELINES_CHARACTERISATION_FORCE_LOG_MANIFEST_H_

#include <string>
#include <vector>

#include "calibration/force_log_reader.h"
#include "calibration/force_test.h"

namespace softbench {

// A characterisation data set (docs/file-formats.md#force-logs): one CSV per
// test plus this YAML manifest, or one combined CSV.
struct ForceLogManifest {
  ForceLogColumns columns;
  // The tests' ids and configurations (statistics empty until read).
  std::vector<ForceTest> tests;
  // Per test, its CSV path (relative paths resolved against the manifest).
  std::vector<std::string> files;
  // Set instead of `files` when the data is one combined CSV.
  std::string combined_path;
};

// Parses a manifest; throws InputError naming the line and key.
ForceLogManifest ParseForceLogManifest(std::string_view yaml,
                                       const std::string& source,
                                       const std::string& base_directory);
ForceLogManifest LoadForceLogManifest(const std::string& path);

// The manifest of synthetic or converted logs (the inverse of the parser).
std::string ForceLogManifestYaml(const ForceLogManifest& manifest,
                                 const std::string& pressure_unit,
                                 const std::string& comment);

// Parses "+fz_n" / "-fy_n" into column and sign; throws InputError naming
// `what`.
void ParseSignedColumn(const std::string& text, const std::string& what,
                       std::string* column, double* sign);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_CHARACTERISATION_FORCE_LOG_MANIFEST_H_
