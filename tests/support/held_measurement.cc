#include "tests/support/held_measurement.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "model/equilibrium.h"
#include "util/check.h"

namespace softbench {

VideoMeasurement HeldMeasurement(const TestPlan& plan, double end_s,
                                 double after_release_mm) {
  const EquilibriumProblem problem(plan.mechanism, plan.force_model);
  EquilibriumSolver solver(problem);
  std::vector<Eigen::VectorXd> held;
  for (const TestPoint& t : plan.tests) {
    SOFTBENCH_CHECK(t.actuate_s && t.release_s);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(problem.NumUnknowns());
    solver.Solve(t.pressures * plan.mpa_per_unit, &x);
    held.push_back(x);
  }
  VideoMeasurement m;
  m.video_path = "held.mp4";
  m.scale_source = "mm_per_px";
  m.mm_per_px = plan.calibration.mm_per_px.value_or(0.1);
  m.mapping = PlaneMapping::FromScale(CameraIntrinsics(), m.mm_per_px, 0.0);
  m.rest_mm.assign(plan.mechanism.NumHeads(), Eigen::Vector2d::Zero());
  m.fps = 30.0;
  m.frame_interval_s = 1.0 / 30.0;
  m.registration = "none (the camera taken to be still)";
  for (int i = 0; i / 30.0 <= end_s; ++i) {
    FrameSample& frame = m.frames.emplace_back();
    frame.frame = i;
    frame.time_s = i / 30.0;
    // The last test actuated by now, if any, and whether it still holds.
    int test = -1;
    for (size_t k = 0; k < plan.tests.size(); ++k) {
      if (*plan.tests[k].actuate_s <= frame.time_s) test = static_cast<int>(k);
    }
    const bool holding =
        test >= 0 && frame.time_s < *plan.tests[test].release_s;
    for (int h = 0; h < plan.mechanism.NumHeads(); ++h) {
      HeadSample& head = frame.heads.emplace_back();
      head.displacement_mm = test < 0 ? Eigen::Vector2d::Zero()
                             : holding
                                 ? Eigen::Vector2d(held[test].segment<2>(2 * h))
                                 : Eigen::Vector2d(after_release_mm, 0.0);
      head.binary_displacement_mm = head.displacement_mm;
      HeadObservation& o = head.observation;
      o.complete = true;
      o.dots_found = 3;
      o.position_mm = m.rest_mm[h] + head.displacement_mm;
      o.binary_position_mm = o.position_mm;
      o.pixel = m.mapping->ToPixel(o.position_mm);
    }
    m.last_frame_s = frame.time_s;
  }
  return m;
}

TestPlan HeldDeltaPlan(const std::string& more_tests) {
  return ParseTestPlan(
      "mechanism: delta\n"
      "pressure_unit: psi\n"
      "calibration: {mm_per_px: 0.1}\n"
      "tests:\n"
      "  - {id: t1, pressures: [6, 6, 0], actuate_s: 2, release_s: 5}\n"
      "  - {id: t2, pressures: [0, 6, 6], actuate_s: 8, release_s: 11}\n"
      "  - {id: t3, pressures: [6, 6, 0], actuate_s: 14, release_s: 17}\n" +
          more_tests,
      "plan.yaml");
}

void LiftHeldHead(const TestPlan& plan, double lift_mm, double noise_mm,
                  double parallax_per_lift, VideoMeasurement* m) {
  std::mt19937 random(32);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (FrameSample& f : m->frames) {
    f.intra = f.frame % 15 == 0;
    const bool held = std::any_of(
        plan.tests.begin(), plan.tests.end(), [&](const TestPoint& t) {
          return t.actuate_s && t.release_s && f.time_s >= *t.actuate_s + 0.5 &&
                 f.time_s < *t.release_s;
        });
    HeadSample& s = f.heads[0];
    s.lift_mm = (held ? lift_mm : 0.0) + noise_mm * noise(random);
    s.tilt_rad.setZero();
    s.parallax_mm = Eigen::Vector2d(parallax_per_lift * s.lift_mm, 0.0);
  }
}

VideoMeasurement SettlingMeasurement(const std::vector<HeadStep>& steps,
                                     double end_s, double tau_s,
                                     double noise_mm) {
  std::mt19937 random(4);
  // Scaled by hand: noise_mm may be 0, which a distribution may not have.
  std::normal_distribution<double> normal;
  VideoMeasurement m;
  m.fps = 30.0;
  m.frame_interval_s = 1.0 / 30.0;
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  const double dt = 1.0 / 30.0;
  for (int frame = 0; frame * dt < end_s; ++frame) {
    const double t = frame * dt;
    // The target during the last frame interval: a step at t shows from the
    // next frame on, as the renderer's continuous settling does.
    Eigen::Vector2d target = Eigen::Vector2d::Zero();
    for (const HeadStep& step : steps) {
      if (t - dt >= step.actuate_s - 1e-9 && t - dt < step.release_s - 1e-9) {
        target = step.target_mm;
      }
    }
    position += (target - position) * (1.0 - std::exp(-dt / tau_s));
    FrameSample sample;
    sample.frame = frame;
    sample.time_s = t;
    HeadSample head;
    head.displacement_mm =
        position + noise_mm * Eigen::Vector2d(normal(random), normal(random));
    head.observation.complete = true;
    head.observation.position_mm = head.displacement_mm;
    sample.heads.push_back(head);
    m.frames.push_back(sample);
  }
  return m;
}

}  // namespace softbench
