#ifndef SOFTBENCH_TESTS_SUPPORT_HELD_MEASUREMENT_H_
#define SOFTBENCH_TESTS_SUPPORT_HELD_MEASUREMENT_H_

#include "pipelines/formats/test_plan.h"
#include "pipelines/measurement/video_measurement.h"

namespace softbench {

// A measurement made up frame by frame, for tests of scoring and reports
// that need no video: frames at 30 fps from 0 to `end_s`, every head at rest
// before the first actuation, at the model's equilibrium for a test's
// pressures from its actuate_s to its release_s, and `after_release_mm`
// along y after a release until the next actuation (a head still on its way
// back, or one that slipped). The plan must give every test's times. The
// pixels come from a fronto-parallel 1080p camera at the plan's mm_per_px
// (0.1 when it gives none).
VideoMeasurement HeldMeasurement(const TestPlan& plan, double end_s,
                                 double after_release_mm);

}  // namespace softbench

#endif  // SOFTBENCH_TESTS_SUPPORT_HELD_MEASUREMENT_H_
