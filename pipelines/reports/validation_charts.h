#ifndef SOFTBENCH_PIPELINES_REPORTS_VALIDATION_CHARTS_H_
#define SOFTBENCH_PIPELINES_REPORTS_VALIDATION_CHARTS_H_

#include <nlohmann/json.hpp>
#include <utility>

#include "pipelines/formats/test_plan.h"
#include "pipelines/measurement/video_measurement.h"
#include "pipelines/validation/validation.h"

namespace softbench {

// The validation report's charts as Vega-Lite specifications, each with a
// title (the report and its tests find charts by title).

// Domains for y and z of the same length (the larger extent of the two, with
// a margin), each centred on its data: drawn in a square, equal axes.
// `values` are objects with fields y and z [mm].
std::pair<nlohmann::json, nlohmann::json> EqualDomains(
    const nlohmann::json& values);

// Fig. 4.8 / 4.16: measured and predicted displacements per scored test and
// head, with lines from each measurement to its predictions, equal axes.
nlohmann::json PositionChart(const TestPlan& plan, const ValidationResult& r);

// Fig. 4.9 / 4.17: error magnitude per scored test for both models.
nlohmann::json ErrorChart(const TestPlan& plan, const ValidationResult& r);
// Each head's lift toward the camera per measured test point (actuated
// less initial), with its U = 2u, and the shift its parallax makes in the
// displacement (issue 27).
nlohmann::json LiftChart(const TestPlan& plan, const ValidationResult& r);

// The trajectory of every head over time, with the windows shaded; lines
// break where frames were not read (windows-only mode).
nlohmann::json TrajectoryChart(const TestPlan& plan, const VideoMeasurement& m,
                               const ValidationResult& r);

// The camera's shift since the reference frame over the whole video (the
// registration to the bench), with the windows shaded and those in which
// the camera moved named; lines break at frames not registered.
nlohmann::json CameraMotionChart(const VideoMeasurement& m,
                                 const ValidationResult& r);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_REPORTS_VALIDATION_CHARTS_H_
