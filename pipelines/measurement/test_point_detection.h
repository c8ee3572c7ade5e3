#ifndef SOFTBENCH_PIPELINES_MEASUREMENT_TEST_POINT_DETECTION_H_
#define SOFTBENCH_PIPELINES_MEASUREMENT_TEST_POINT_DETECTION_H_

#include <optional>
#include <string>
#include <vector>

#include "pipelines/measurement/video_measurement.h"

namespace softbench {

// Finding the test points of a bench video from the motion itself, for plans
// without times: the heads rest at zero pressure between test points and
// hold a displaced position while the pressures are applied (thesis 4.1.3).
struct TestPointDetectionOptions {
  // Motion [mm] (the largest head distance from rest) that counts as
  // actuated: at least this, and at least `noise_factor` times the motion
  // of the quietest tenth of the frames (the measurement's rest noise).
  double min_motion_mm = 0.01;
  double noise_factor = 10.0;
  // Excursions closer than this are one test point; shorter ones are noise.
  double min_gap_s = 0.3;
  double min_hold_s = 0.3;
  // Actuation and release are where the motion crosses this fraction of the
  // way between rest and the hold's level: close to the step itself for any
  // first-order settling (0.1 tau after it), and clear of the noise.
  double crossing_fraction = 0.1;

  std::optional<std::string> Problem() const;
};

struct DetectedTestPoint {
  double actuate_s = 0.0;
  double release_s = 0.0;
  double hold_motion_mm = 0.0;  // the motion's level at the end of the hold
};

struct TestPointDetection {
  bool found = false;
  std::string why_not;
  double threshold_mm = 0.0;
  std::vector<DetectedTestPoint> points;
};

// Finds `expected` test points in a measured video (its frames' head
// displacements). Fails, saying what it found, when the count differs.
TestPointDetection DetectTestPoints(const VideoMeasurement& measurement,
                                    int expected,
                                    const TestPointDetectionOptions& options);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_MEASUREMENT_TEST_POINT_DETECTION_H_
