#ifndef SOFTBENCH_PIPELINES_REPORTS_VALIDATION_FILES_H_
#define SOFTBENCH_PIPELINES_REPORTS_VALIDATION_FILES_H_

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "pipelines/formats/test_plan.h"
#include "pipelines/measurement/video_measurement.h"
#include "pipelines/validation/validate_video.h"
#include "util/atomic_file.h"

namespace softbench {

// The per-frame trajectory CSV (docs/file-formats.md).
std::string TrajectoryCsv(const TestPlan& plan,
                          const VideoMeasurement& measurement);

// results.csv of a validation (docs/file-formats.md): one row per test and
// head, each ending with the softbench version, the pressure unit and every
// input's file name and SHA-256, so a row copied elsewhere keeps its origin.
std::string ResultsCsv(const VideoValidation& v);

// summary.json of a validation (docs/file-formats.md).
nlohmann::json SummaryJson(const VideoValidation& v);

// The four report files of one video (report.html, results.csv,
// summary.json, trajectory.csv) into `directory`, each atomically.
void WriteValidationFiles(const VideoValidation& v,
                          const std::string& directory);

// index.html and index.csv of several videos' reports, each in the folder
// `names[i]` of `report`.
void WriteValidationIndex(const std::vector<VideoValidation>& videos,
                          const std::vector<std::string>& names,
                          const AtomicDirectory& report);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_REPORTS_VALIDATION_FILES_H_
