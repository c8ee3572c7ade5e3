#include "pipelines/synthetic/render_timeline.h"

#include <cmath>
#include <numbers>
#include <random>

#include "model/equilibrium.h"
#include "util/check.h"
#include "util/input_error.h"

namespace softbench {

void AssignTimes(TestPlan* plan) {
  if (plan->HasTimes()) return;
  double t = plan->scene.lead_in_s;
  for (TestPoint& test : plan->tests) {
    test.actuate_s = t;
    test.release_s = t + plan->scene.hold_s;
    t = *test.release_s + plan->scene.rest_s;
  }
}

double RenderedDurationS(TestPlan plan) {
  SOFTBENCH_CHECK(!plan.tests.empty()) << plan.path << ": a plan without tests";
  AssignTimes(&plan);
  return *plan.tests.back().release_s + plan.scene.rest_s;
}

namespace {

// Each head's lift and tilt in one test: lift uniform in [0, max], tilt of
// a magnitude uniform in [0, max] in a uniform direction, from a seed of
// the test's index (so every render of a plan agrees).
Eigen::VectorXd OutOfPlane(const SceneSpec& scene, int num_heads, size_t test) {
  Eigen::VectorXd pose = Eigen::VectorXd::Zero(3 * num_heads);
  std::mt19937_64 rng(0x11F7ULL * (test + 1));
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int h = 0; h < num_heads; ++h) {
    const double lift = scene.head_lift_mm * unit(rng);
    const double tilt =
        scene.head_tilt_deg * std::numbers::pi / 180.0 * unit(rng);
    const double direction = 2.0 * std::numbers::pi * unit(rng);
    pose.segment<3>(3 * h) << lift, tilt * std::cos(direction),
        tilt * std::sin(direction);
  }
  return pose;
}

}  // namespace

HeadTimeline::HeadTimeline(const TestPlan& plan)
    : scene_(plan.scene),
      num_unknowns_(plan.mechanism.NumUnknowns()),
      state_size_(num_unknowns_ + 3 * plan.mechanism.NumHeads()),
      duration_s_(RenderedDurationS(plan)) {
  SOFTBENCH_CHECK(plan.HasTimes()) << plan.path << ": call AssignTimes first";
  const EquilibriumProblem problem(plan.mechanism, plan.force_model);
  EquilibriumSolver solver(problem);
  Eigen::VectorXd slip = Eigen::VectorXd::Zero(state_size_);
  events_.push_back({0.0, slip, -1});
  for (size_t i = 0; i < plan.tests.size(); ++i) {
    const TestPoint& test = plan.tests[i];
    Eigen::VectorXd x = Eigen::VectorXd::Zero(num_unknowns_);
    const EquilibriumSummary summary =
        solver.Solve(test.pressures * plan.mpa_per_unit, &x);
    if (!summary.converged()) {
      throw InputError(plan.path + ": test '" + test.id +
                       "': no equilibrium for its pressures (" +
                       summary.Message() + ")");
    }
    equilibria_.push_back(x);
    out_of_plane_.push_back(
        OutOfPlane(plan.scene, plan.mechanism.NumHeads(), i));
    Eigen::VectorXd target = slip;
    target.head(num_unknowns_) += x;
    target.tail(out_of_plane_.back().size()) = out_of_plane_.back();
    events_.push_back({*test.actuate_s, target, static_cast<int>(i)});
    for (int h = 0; h < plan.mechanism.NumHeads(); ++h) {
      slip.segment<2>(2 * h) += test.residual_offset_mm;
    }
    events_.push_back({*test.release_s, slip, -1});
  }
}

Eigen::VectorXd HeadTimeline::DisplacementAt(double time_s) const {
  return StateAt(time_s).head(num_unknowns_);
}

Eigen::VectorXd HeadTimeline::StateAt(double time_s) const {
  // x(t) = target(t) + (x(t_k) - target(t_k)) exp(-(t - t_k) / tau) after the
  // last event t_k, evaluated event by event from rest.
  Eigen::VectorXd x = Eigen::VectorXd::Zero(state_size_);
  const auto target_at = [&](const Event& e, double t) {
    if (e.holding_test < 0 || scene_.creep_fraction == 0.0) return e.target;
    const double creep =
        scene_.creep_fraction *
        (1.0 - std::exp(-(t - e.time_s) / scene_.creep_time_constant_s));
    Eigen::VectorXd target = e.target;
    target.head(num_unknowns_) += creep * equilibria_[e.holding_test];
    return target;
  };
  for (size_t k = 0; k < events_.size(); ++k) {
    const Event& e = events_[k];
    if (e.time_s > time_s) break;
    const bool last = k + 1 == events_.size() || events_[k + 1].time_s > time_s;
    const double end = last ? time_s : events_[k + 1].time_s;
    const double decay =
        std::exp(-(end - e.time_s) / scene_.settle_time_constant_s);
    x = target_at(e, end) + (x - target_at(e, e.time_s)) * decay;
  }
  return x;
}

}  // namespace softbench
