#include "pipelines/synthetic/render_timeline.h"

#include <cmath>

#include "model/equilibrium.h"
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

HeadTimeline::HeadTimeline(const TestPlan& plan)
    : scene_(plan.scene), num_unknowns_(plan.mechanism.NumUnknowns()) {
  const EquilibriumProblem problem(plan.mechanism, plan.force_model);
  EquilibriumSolver solver(problem);
  Eigen::VectorXd slip = Eigen::VectorXd::Zero(num_unknowns_);
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
    events_.push_back({*test.actuate_s, slip + x, static_cast<int>(i)});
    for (int h = 0; h < plan.mechanism.NumHeads(); ++h) {
      slip.segment<2>(2 * h) += test.residual_offset_mm;
    }
    events_.push_back({*test.release_s, slip, -1});
  }
  duration_s_ = *plan.tests.back().release_s + plan.scene.rest_s;
}

Eigen::VectorXd HeadTimeline::DisplacementAt(double time_s) const {
  // x(t) = target(t) + (x(t_k) - target(t_k)) exp(-(t - t_k) / tau) after the
  // last event t_k, evaluated event by event from rest.
  Eigen::VectorXd x = Eigen::VectorXd::Zero(num_unknowns_);
  const auto target_at = [&](const Event& e, double t) {
    if (e.holding_test < 0 || scene_.creep_fraction == 0.0) return e.target;
    const double creep =
        scene_.creep_fraction *
        (1.0 - std::exp(-(t - e.time_s) / scene_.creep_time_constant_s));
    return Eigen::VectorXd(e.target + creep * equilibria_[e.holding_test]);
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
