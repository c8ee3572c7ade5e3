#ifndef SOFTBENCH_TESTS_SUPPORT_HELD_MEASUREMENT_H_
#define SOFTBENCH_TESTS_SUPPORT_HELD_MEASUREMENT_H_

#include <Eigen/Core>
#include <string>
#include <vector>

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

// A delta plan of three timed tests (t3 repeats t1's pressures), actuated
// at 2, 8 and 14 s and released 3 s later, in psi at 0.1 mm/px, followed by
// `more_tests` (YAML list items, e.g. a skipped test).
TestPlan HeldDeltaPlan(const std::string& more_tests = "");

// Gives `m` an I picture every 15 frames (so the codec's term has its
// jumps) and raises head 0 toward the camera by `lift_mm` while a test
// holds it (from 0.5 s after its actuate_s to its release_s), each frame's
// lift with Gaussian noise of `noise_mm` (fixed seed), and records its
// parallax as `parallax_per_lift` mm along y per mm of lift. The positions
// are not moved.
void LiftHeldHead(const TestPlan& plan, double lift_mm, double noise_mm,
                  double parallax_per_lift, VideoMeasurement* m);

// A pressure step of one head: toward `target_mm` from actuate_s, back to
// rest from release_s.
struct HeadStep {
  double actuate_s, release_s;
  Eigen::Vector2d target_mm;
};

// One head settling first-order (tau) toward each step's target and back,
// at 30 fps from 0 to `end_s`, with Gaussian measurement noise (fixed seed):
// each frame's displacement and observed position, every dot found.
VideoMeasurement SettlingMeasurement(const std::vector<HeadStep>& steps,
                                     double end_s, double tau_s,
                                     double noise_mm);

}  // namespace softbench

#endif  // SOFTBENCH_TESTS_SUPPORT_HELD_MEASUREMENT_H_
