#include "model/equilibrium.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

#include "util/check.h"

namespace softbench {

EquilibriumProblem::EquilibriumProblem(Mechanism mechanism,
                                       const ForceModel& model)
    : mechanism_(std::move(mechanism)), model_(model) {
  SOFTBENCH_CHECK(!mechanism_.Problem() && !model_.constants.Problem())
      << "EquilibriumSolver needs a checked mechanism and constants";
  links_.reserve(mechanism_.actuators.size());
  for (const Actuator& actuator : mechanism_.actuators) {
    const bool on_head = actuator.anchor.kind == AnchorRef::Kind::kHead;
    const Eigen::Matrix2d world_from_local =
        RotationX(mechanism_.RestAxisRotation(actuator));
    links_.push_back({world_from_local(0, 0), world_from_local(1, 0),
                      mechanism_.heads[actuator.head].rest_mm -
                          mechanism_.AnchorRestPosition(actuator),
                      mechanism_.RestLength(actuator), actuator.head,
                      on_head ? actuator.anchor.index : -1});
  }
}

Eigen::Vector2d EquilibriumProblem::LocalVector(
    const Link& link, const Eigen::VectorXd& x) const {
  Eigen::Vector2d w = link.rest_vector_mm + x.segment<2>(2 * link.head);
  if (link.anchor_head >= 0) w -= x.segment<2>(2 * link.anchor_head);
  // v = R^T w.
  return {link.cos_axis * w.x() + link.sin_axis * w.y(),
          -link.sin_axis * w.x() + link.cos_axis * w.y()};
}

namespace {

// One link's share of d(residual)/dx: the head at rows and columns h, h + 1,
// and the anchor's head (a >= 0) with the opposite sign. c and s are the
// actuator's axis rotation R = [[c, -s], [s, c]]; w = (wy, wz) runs from the
// anchor to the head, |w| = length.
//   dF_world/dh = R (dF/d(dL) d(dL)/dv^T + dF/dtheta d(theta)/dv^T) R^T
//               = (R dF/d(dL)) u^T + (R dF/dtheta) (perp(w) / |w|^2)^T,
// since d(dL)/dv = v/|v| maps to u = w/|w|, d(theta)/dv = (-v_z, v_y)/|v|^2
// maps to perp(w) = (-w_z, w_y), and R commutes with the quarter turn.
inline void AddStateJacobian(const ActuatorForce& force, double c, double s,
                             double wy, double wz, double length,
                             double length_sq, int h, int a,
                             Eigen::MatrixXd* jacobian_x) {
  const Eigen::Vector2d& dl = force.d_force_d_delta_length;
  const Eigen::Vector2d& dt = force.d_force_d_theta;
  const double ly = c * dl.x() - s * dl.y(), lz = s * dl.x() + c * dl.y();
  const double ty = c * dt.x() - s * dt.y(), tz = s * dt.x() + c * dt.y();
  const double uy = wy / length, uz = wz / length;
  const double py = -wz / length_sq, pz = wy / length_sq;
  const double g00 = ly * uy + ty * py, g01 = ly * uz + ty * pz;
  const double g10 = lz * uy + tz * py, g11 = lz * uz + tz * pz;
  Eigen::MatrixXd& j = *jacobian_x;
  j(h, h) += g00, j(h, h + 1) += g01, j(h + 1, h) += g10,
      j(h + 1, h + 1) += g11;
  if (a >= 0) {
    j(h, a) -= g00, j(h, a + 1) -= g01, j(h + 1, a) -= g10,
        j(h + 1, a + 1) -= g11;
    j(a, h) -= g00, j(a, h + 1) -= g01, j(a + 1, h) -= g10,
        j(a + 1, h + 1) -= g11;
    j(a, a) += g00, j(a, a + 1) += g01, j(a + 1, a) += g10,
        j(a + 1, a + 1) += g11;
  }
}

// One link's share of d(residual)/d(pressure k): R dF/dP on the head, and
// its opposite on the anchor's head (a >= 0).
inline void AddPressureJacobian(const ActuatorForce& force, double c, double s,
                                int k, int h, int a,
                                Eigen::MatrixXd* jacobian_pressure) {
  const Eigen::Vector2d& dp = force.d_force_d_pressure;
  const double py = c * dp.x() - s * dp.y(), pz = s * dp.x() + c * dp.y();
  (*jacobian_pressure)(h, k) += py;
  (*jacobian_pressure)(h + 1, k) += pz;
  if (a >= 0) {
    (*jacobian_pressure)(a, k) -= py;
    (*jacobian_pressure)(a + 1, k) -= pz;
  }
}

}  // namespace

bool EquilibriumProblem::Evaluate(const Eigen::VectorXd& pressures_mpa,
                                  const Eigen::VectorXd& x,
                                  Eigen::VectorXd* residual_n,
                                  Eigen::MatrixXd* jacobian_x,
                                  Eigen::MatrixXd* jacobian_pressure) const {
  const int n = NumUnknowns();
  SOFTBENCH_CHECK(x.size() == n && pressures_mpa.size() == NumActuators())
      << "state or pressures of the wrong size";
  residual_n->setZero(n);
  if (jacobian_x) jacobian_x->setZero(n, n);
  if (jacobian_pressure) jacobian_pressure->setZero(n, NumActuators());

  // Written out in scalars in the world frame: these loops are the cost of
  // every Newton iteration and every workspace point. Links go in batches:
  // first the geometry of the whole batch, whose square roots and arc
  // tangents do not depend on each other and so overlap in the processor,
  // then the forces.
  constexpr int kBatch = 8;
  const int num_links = static_cast<int>(links_.size());
  for (int first = 0; first < num_links; first += kBatch) {
    const int batch = std::min(kBatch, num_links - first);
    double w_y[kBatch], w_z[kBatch], lengths_sq[kBatch], lengths[kBatch],
        thetas[kBatch];
    for (int i = 0; i < batch; ++i) {
      const Link& link = links_[first + i];
      // w = h - a in the world frame; v = R^T w in the local frame.
      double wy = link.rest_vector_mm.x() + x[2 * link.head];
      double wz = link.rest_vector_mm.y() + x[2 * link.head + 1];
      if (link.anchor_head >= 0) {
        wy -= x[2 * link.anchor_head];
        wz -= x[2 * link.anchor_head + 1];
      }
      w_y[i] = wy;
      w_z[i] = wz;
      lengths_sq[i] = wy * wy + wz * wz;
      lengths[i] = std::sqrt(lengths_sq[i]);
      const double vy = link.cos_axis * wy + link.sin_axis * wz;
      const double vz = -link.sin_axis * wy + link.cos_axis * wz;
      thetas[i] = std::atan2(-vy, vz);  // theta as defined in model.md
    }
    for (int i = 0; i < batch; ++i) {
      const int k = first + i;
      const Link& link = links_[k];
      if (!(lengths[i] > 1e-9 * link.rest_length_mm)) return false;
      const int h = 2 * link.head;
      const int a = 2 * link.anchor_head;
      const double c = link.cos_axis;  // R = [[c, -s], [s, c]]
      const double s = link.sin_axis;
      const double wy = w_y[i], wz = w_z[i];
      const double length = lengths[i], length_sq = lengths_sq[i];
      // dL as defined in model.md ("One actuator").
      const Deformation deformation{length - link.rest_length_mm, thetas[i]};
      const ActuatorForce force =
          EvaluateActuatorForce(model_, pressures_mpa[k], deformation);
      // World force R F_local on the head; the anchor end feels the opposite.
      const double fy =
          c * force.force_in_local_n.x() - s * force.force_in_local_n.y();
      const double fz =
          s * force.force_in_local_n.x() + c * force.force_in_local_n.y();
      (*residual_n)[h] += fy;
      (*residual_n)[h + 1] += fz;
      if (link.anchor_head >= 0) {
        (*residual_n)[a] -= fy;
        (*residual_n)[a + 1] -= fz;
      }

      if (jacobian_x) {
        AddStateJacobian(force, c, s, wy, wz, length, length_sq, h,
                         link.anchor_head >= 0 ? a : -1, jacobian_x);
      }
      if (jacobian_pressure) {
        AddPressureJacobian(force, c, s, k, h, link.anchor_head >= 0 ? a : -1,
                            jacobian_pressure);
      }
    }
  }
  return residual_n->allFinite();
}

std::vector<Deformation> EquilibriumProblem::Deformations(
    const Eigen::VectorXd& x) const {
  std::vector<Deformation> out;
  out.reserve(links_.size());
  for (const Link& link : links_) {
    const Eigen::Vector2d v = LocalVector(link, x);
    out.push_back({v.norm() - link.rest_length_mm, std::atan2(-v.x(), v.y())});
  }
  return out;
}

std::optional<std::string> EquilibriumOptions::Problem() const {
  if (!(function_tolerance_n > 0.0)) return "function_tolerance_n must be > 0";
  if (max_iterations < 1) return "max_iterations must be >= 1";
  if (max_step_halvings < 0) return "max_step_halvings must be >= 0";
  if (max_damped_attempts < 0) return "max_damped_attempts must be >= 0";
  return std::nullopt;
}

std::string EquilibriumSummary::Message() const {
  char force[32];
  std::snprintf(force, sizeof(force), "%.2e", max_residual_n);
  const std::string figures = " after " + std::to_string(iterations) +
                              " iterations, largest net force " + force + " N";
  switch (termination) {
    case EquilibriumTermination::kConverged:
      return "converged" + figures;
    case EquilibriumTermination::kMaxIterations:
      return "not converged: iteration limit reached" + figures;
    case EquilibriumTermination::kNoDescent:
      return "not converged: no step reduced the net force" + figures;
    case EquilibriumTermination::kInvalidStartingPoint:
      return "not converged: the model is undefined at the starting point (an "
             "actuator has zero length)";
  }
  return "unknown termination";
}

EquilibriumSolver::EquilibriumSolver(const EquilibriumProblem& problem,
                                     const EquilibriumOptions& options)
    : problem_(problem),
      options_(options),
      residual_(problem.NumUnknowns()),
      trial_residual_(problem.NumUnknowns()),
      step_(problem.NumUnknowns()),
      trial_x_(problem.NumUnknowns()),
      jacobian_(problem.NumUnknowns(), problem.NumUnknowns()),
      trial_jacobian_(problem.NumUnknowns(), problem.NumUnknowns()),
      normal_matrix_(problem.NumUnknowns(), problem.NumUnknowns()),
      curvature_(problem.NumUnknowns(), problem.NumActuators()),
      has_curvature_(problem.NumActuators(), false),
      lu_(problem.NumUnknowns()) {
  SOFTBENCH_CHECK(!options_.Problem()) << *options_.Problem();
}

bool EquilibriumSolver::TryDampedStep(const Eigen::VectorXd& pressures_mpa,
                                      Eigen::VectorXd* x, double* norm) {
  // Levenberg-Marquardt: (J^T J + mu diag(J^T J)) dx = -J^T r. Reached only
  // when the Newton direction fails, e.g. near a fold of the force field.
  normal_matrix_.noalias() = jacobian_.transpose() * jacobian_;
  const Eigen::VectorXd gradient = jacobian_.transpose() * residual_;
  const Eigen::VectorXd diagonal =
      normal_matrix_.diagonal().cwiseMax(1e-12 * normal_matrix_.trace());
  for (int attempt = 0; attempt < options_.max_damped_attempts; ++attempt) {
    Eigen::MatrixXd damped = normal_matrix_;
    damped.diagonal() += damping_ * diagonal;
    step_ = -damped.ldlt().solve(gradient);
    trial_x_ = *x + step_;
    if (step_.allFinite() &&
        problem_.Evaluate(pressures_mpa, trial_x_, &trial_residual_) &&
        trial_residual_.norm() < *norm) {
      *x = trial_x_;
      *norm = trial_residual_.norm();
      damping_ = std::max(damping_ / 10.0, 1e-12);
      return true;
    }
    damping_ *= 10.0;
  }
  return false;
}

namespace {

// a x = b for N unknowns with fixed-size Eigen types: the thesis mechanisms
// have 2 and 4 unknowns, where a dynamic LU costs more than the whole force
// evaluation. Up to 4x4 Eigen inverts in closed form (unrolled cofactors);
// the stiffness matrices are well conditioned away from folds, and a poor
// step is caught by the line search and the residual test anyway.
template <int N>
void SolveFixedSize(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                    Eigen::VectorXd* x) {
  const Eigen::Matrix<double, N, N> a_fixed = a;
  const Eigen::Matrix<double, N, 1> b_fixed = b;
  if constexpr (N <= 4) {
    *x = a_fixed.inverse() * b_fixed;
  } else {
    *x = a_fixed.partialPivLu().solve(b_fixed);
  }
}

void SolveLinear(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                 Eigen::PartialPivLU<Eigen::MatrixXd>* lu, Eigen::VectorXd* x) {
  switch (a.rows()) {
    case 2:
      return SolveFixedSize<2>(a, b, x);
    case 4:
      return SolveFixedSize<4>(a, b, x);
    case 6:
      return SolveFixedSize<6>(a, b, x);
    default:
      lu->compute(a);
      x->noalias() = lu->solve(b);
  }
}

}  // namespace

void EquilibriumSolver::PredictSolution(const Eigen::VectorXd& pressures_mpa,
                                        Eigen::VectorXd* x) {
  predicted_axis_ = -1;
  if (!has_solution_) return;
  // The net force is linear in P, so at the last solution
  //   R(x + dx, P + dP) ~ J dx + dR/dP dP = 0.
  step_pressures_ = pressures_mpa - last_pressures_;
  tangent_rhs_.noalias() = jacobian_pressure_ * step_pressures_;
  SolveLinear(jacobian_, tangent_rhs_, &lu_, &step_);
  if (!step_.allFinite()) return;
  linear_prediction_ = last_solution_ - step_;  // x_last + x'
  *x = linear_prediction_;

  int axis = -1;
  for (int a = 0; a < step_pressures_.size(); ++a) {
    if (step_pressures_[a] == 0.0) continue;
    if (axis >= 0) return;  // several actuators change: first order only
    axis = a;
  }
  if (axis < 0) return;
  predicted_axis_ = axis;
  if (has_curvature_[axis]) {
    *x +=
        curvature_.col(axis) * (step_pressures_[axis] * step_pressures_[axis]);
  }
}

EquilibriumSummary EquilibriumSolver::Solve(
    const Eigen::VectorXd& pressures_mpa, Eigen::VectorXd* x) {
  EquilibriumSummary summary;
  has_solution_ = false;
  // A prediction is for the one solve that follows it.
  const int predicted_axis = std::exchange(predicted_axis_, -1);
  if (!problem_.Evaluate(pressures_mpa, *x, &residual_, &jacobian_,
                         &jacobian_pressure_)) {
    summary.termination = EquilibriumTermination::kInvalidStartingPoint;
    summary.max_residual_n = std::numeric_limits<double>::infinity();
    return summary;
  }
  for (;;) {
    summary.max_residual_n = residual_.lpNorm<Eigen::Infinity>();
    if (summary.max_residual_n <= options_.function_tolerance_n) {
      summary.termination = EquilibriumTermination::kConverged;
      // What the first-order prediction missed is (1/2) x'' dP^2 to third
      // order: remember it for the next step of the same actuator.
      if (predicted_axis >= 0) {
        const double step_mpa = step_pressures_[predicted_axis];
        curvature_.col(predicted_axis) =
            (*x - linear_prediction_) / (step_mpa * step_mpa);
        has_curvature_[predicted_axis] = true;
      }
      last_solution_ = *x;
      last_pressures_ = pressures_mpa;
      has_solution_ = true;
      return summary;
    }
    if (summary.iterations == options_.max_iterations) {
      summary.termination = EquilibriumTermination::kMaxIterations;
      return summary;
    }
    ++summary.iterations;

    // Newton direction with backtracking (Armijo on |r|). Trial points are
    // evaluated with their Jacobian: the first one is nearly always taken.
    double norm = residual_.norm();
    SolveLinear(jacobian_, residual_, &lu_, &step_);
    bool accepted = false;
    if (step_.allFinite()) {
      double alpha = 1.0;
      for (int i = 0; i <= options_.max_step_halvings; ++i, alpha *= 0.5) {
        trial_x_ = *x - alpha * step_;
        if (problem_.Evaluate(pressures_mpa, trial_x_, &trial_residual_,
                              &trial_jacobian_, &trial_jacobian_pressure_) &&
            trial_residual_.norm() <= (1.0 - 1e-4 * alpha) * norm) {
          x->swap(trial_x_);
          residual_.swap(trial_residual_);
          jacobian_.swap(trial_jacobian_);
          jacobian_pressure_.swap(trial_jacobian_pressure_);
          accepted = true;
          break;
        }
      }
    }
    if (!accepted) {
      ++summary.damped_steps;
      if (!TryDampedStep(pressures_mpa, x, &norm)) {
        summary.termination = EquilibriumTermination::kNoDescent;
        return summary;
      }
      problem_.Evaluate(pressures_mpa, *x, &residual_, &jacobian_,
                        &jacobian_pressure_);
    }
  }
}

}  // namespace softbench
