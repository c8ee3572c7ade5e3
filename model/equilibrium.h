#ifndef SOFTBENCH_MODEL_EQUILIBRIUM_H_
#define SOFTBENCH_MODEL_EQUILIBRIUM_H_

#include <Eigen/Core>
#include <Eigen/LU>
#include <optional>
#include <string>
#include <vector>

#include "model/actuator_model.h"
#include "model/mechanism.h"

namespace softbench {

// The static equilibrium of a mechanism under given pressures (thesis Eq. 4.6,
// 4.18 / 4.19): for every head, the world forces of the actuators that touch
// it sum to zero. Unknowns x: each head's (y, z) displacement from rest [mm],
// stacked head by head. The anchor end of an actuator that ends on a head
// feels the opposite force.
class EquilibriumProblem {
 public:
  // `mechanism` must pass Mechanism::Problem() and `model.constants` must pass
  // ActuatorConstants::Problem(); both are programmer errors otherwise.
  EquilibriumProblem(Mechanism mechanism, const ForceModel& model);

  const Mechanism& mechanism() const { return mechanism_; }
  const ForceModel& model() const { return model_; }
  int NumUnknowns() const { return mechanism_.NumUnknowns(); }
  int NumActuators() const { return mechanism_.NumActuators(); }

  // Net world force on every head [N] at displacements x and pressures [MPa];
  // optionally its Jacobians d(residual)/dx [N/mm] and d(residual)/dP [N/MPa]
  // (analytic). Returns false where the model is undefined (an actuator
  // collapsed to zero length) or the result is not finite.
  bool Evaluate(const Eigen::VectorXd& pressures_mpa, const Eigen::VectorXd& x,
                Eigen::VectorXd* residual_n,
                Eigen::MatrixXd* jacobian_x = nullptr,
                Eigen::MatrixXd* jacobian_pressure = nullptr) const;

  // Each actuator's (dL, theta) at displacements x, in actuator order.
  std::vector<Deformation> Deformations(const Eigen::VectorXd& x) const;

 private:
  // Geometry of one actuator, precomputed from the mechanism.
  struct Link {
    // world_from_local = [[cos, -sin], [sin, cos]] of the rest axis.
    double cos_axis, sin_axis;
    // The head's rest position minus the anchor's [mm], world frame: the
    // actuator's vector is this plus the head's minus the anchor's
    // displacement.
    Eigen::Vector2d rest_vector_mm;
    double rest_length_mm;
    int head;
    int anchor_head;  // -1 for a fixed anchor
  };
  Eigen::Vector2d LocalVector(const Link& link, const Eigen::VectorXd& x) const;

  Mechanism mechanism_;
  ForceModel model_;
  std::vector<Link> links_;
};

struct EquilibriumOptions {
  // Converged when every component of the net force is at most this [N].
  double function_tolerance_n = 1e-10;
  // Newton iterations (each possibly with a line search or damped steps).
  int max_iterations = 50;
  // Step halvings tried in the backtracking line search before falling back
  // to Levenberg-Marquardt damped steps.
  int max_step_halvings = 20;
  // Damped (Levenberg-Marquardt) step attempts per iteration after the line
  // search fails; the damping grows tenfold on each rejected attempt.
  int max_damped_attempts = 12;

  std::optional<std::string> Problem() const;
};

enum class EquilibriumTermination {
  kConverged,
  kMaxIterations,         // still above tolerance after max_iterations
  kNoDescent,             // neither Newton nor damped steps reduced the force
  kInvalidStartingPoint,  // model undefined at the initial guess
};

struct EquilibriumSummary {
  EquilibriumTermination termination = EquilibriumTermination::kMaxIterations;
  int iterations = 0;
  int damped_steps = 0;         // iterations that needed the fallback
  double max_residual_n = 0.0;  // largest |net force| component at the end

  bool converged() const {
    return termination == EquilibriumTermination::kConverged;
  }
  // One line for people: what happened and, if not converged, why.
  std::string Message() const;
};

// Newton's method with the analytic Jacobian, a backtracking line search on
// |residual|, and a Levenberg-Marquardt fallback when the line search fails.
// Holds its own workspace so repeated solves do not allocate; one solver per
// thread.
class EquilibriumSolver {
 public:
  explicit EquilibriumSolver(const EquilibriumProblem& problem,
                             const EquilibriumOptions& options = {});

  // Solves for x starting from *x (the rest state zero, or a neighbouring
  // solution). On return *x holds the last iterate; it is an equilibrium only
  // if the summary says converged.
  EquilibriumSummary Solve(const Eigen::VectorXd& pressures_mpa,
                           Eigen::VectorXd* x);

  // Continuation predictor: when the last Solve() converged, sets *x to a
  // prediction of the solution at the new pressures, so that the solve
  // started there needs fewer Newton iterations. To first order it moves
  // along the solution path's tangent
  //   x' = -J^-1 (dR/dP) (P_new - P_last),
  // exact to first order because the net force is linear in P. When only one
  // actuator's pressure changes (a sweep), it adds the second-order term
  // (1/2) x'' dP^2 along that actuator, remembered from the last solve that
  // stepped the same actuator: the difference between where that solve
  // converged and its first-order prediction, per MPa^2. The curvature of the
  // solution path changes little from one configuration to its neighbours,
  // so the error left is third order in the step. Leaves *x alone when the
  // last solve did not converge. The prediction is for the next Solve(),
  // which must be at the same pressures.
  void PredictSolution(const Eigen::VectorXd& pressures_mpa,
                       Eigen::VectorXd* x);

 private:
  bool TryDampedStep(const Eigen::VectorXd& pressures_mpa, Eigen::VectorXd* x,
                     double* norm);

  const EquilibriumProblem& problem_;
  EquilibriumOptions options_;
  Eigen::VectorXd residual_, trial_residual_, step_, trial_x_;
  Eigen::MatrixXd jacobian_, trial_jacobian_, normal_matrix_;
  // d(residual)/dP at the current and trial iterates, for the predictor.
  Eigen::MatrixXd jacobian_pressure_, trial_jacobian_pressure_;
  // The last converged solution and its pressures, for the predictor.
  Eigen::VectorXd last_solution_, last_pressures_;
  // Column a: the remembered second-order term of the solution path along
  // actuator a [mm/MPa^2], valid where has_curvature_[a].
  Eigen::MatrixXd curvature_;
  std::vector<bool> has_curvature_;
  // The last prediction's first-order part, its pressure step [MPa] and the
  // actuator it stepped (-1 when several or none changed): Solve() learns
  // the curvature from them.
  Eigen::VectorXd linear_prediction_, step_pressures_;
  int predicted_axis_ = -1;
  // PredictSolution's workspace.
  Eigen::VectorXd tangent_rhs_;
  bool has_solution_ = false;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  double damping_ = 1e-6;
};

}  // namespace softbench

#endif  // SOFTBENCH_MODEL_EQUILIBRIUM_H_
