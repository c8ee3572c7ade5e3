#ifndef SOFTBENCH_PIPELINES_SYNTHETIC_RENDER_TIMELINE_H_
#define SOFTBENCH_PIPELINES_SYNTHETIC_RENDER_TIMELINE_H_

#include <Eigen/Core>
#include <vector>

#include "pipelines/formats/test_plan.h"

namespace softbench {

// Where the heads are at any time of a rendered test plan: at each actuation
// the target becomes the model's equilibrium for the test's pressures, at each
// release the rest position (plus any residual offset, which stays: a slip);
// the heads follow the target with first-order settling (time constant
// scene.settle_time_constant_s) and, while actuated, an optional creep toward
// (1 + creep_fraction) times the equilibrium. Heads may also rise and tilt
// out of the plane while actuated (scene.head_lift_mm, head_tilt_deg),
// settling the same way.
class HeadTimeline {
 public:
  // Throws InputError when a test's equilibrium cannot be found. `plan` must
  // have times (see AssignTimes).
  explicit HeadTimeline(const TestPlan& plan);

  // Displacements (y1, z1, y2, z2, ...) [mm] from rest at `time_s`.
  Eigen::VectorXd DisplacementAt(double time_s) const;
  // The heads' state at `time_s`: the displacements, then per head its
  // lift toward the camera [mm] and tilt about world y and z [rad]
  // (SceneRenderer's head state).
  Eigen::VectorXd StateAt(double time_s) const;
  // The lift and tilt each test gives each head: (lift, tilt y, tilt z)
  // per head, in test order.
  const std::vector<Eigen::VectorXd>& out_of_plane() const {
    return out_of_plane_;
  }
  // The equilibrium of each test's pressures, in test order.
  const std::vector<Eigen::VectorXd>& equilibria() const { return equilibria_; }
  // Last release plus the plan's rest time.
  double duration_s() const { return duration_s_; }

 private:
  struct Event {
    double time_s;
    Eigen::VectorXd target;  // without creep
    int holding_test;        // test index while actuated, else -1
  };
  std::vector<Event> events_;
  std::vector<Eigen::VectorXd> equilibria_;
  std::vector<Eigen::VectorXd> out_of_plane_;
  SceneSpec scene_;
  int num_unknowns_ = 0;
  int state_size_ = 0;
  double duration_s_ = 0.0;
};

// Gives every test actuate_s and release_s when the plan has none: lead-in,
// then hold and rest per test (scene section). Plans with times are kept.
void AssignTimes(TestPlan* plan);

// How long a rendered video of `plan` lasts [s]: its last release plus the
// scene's rest time, with the times AssignTimes gives a plan that has none.
double RenderedDurationS(TestPlan plan);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_SYNTHETIC_RENDER_TIMELINE_H_
