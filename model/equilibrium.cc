#include "model/equilibrium.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <limits>

namespace softbench {

EquilibriumProblem::EquilibriumProblem(const Mechanism& mechanism,
                                       const ForceModel& model)
    : mechanism_(mechanism), model_(model) {
  assert(!mechanism_.Check() && !model_.constants.Check());
  links_.reserve(mechanism_.actuators.size());
  for (const Actuator& actuator : mechanism_.actuators) {
    const bool on_head = actuator.anchor.kind == AnchorRef::Kind::kHead;
    links_.push_back({RotationX(mechanism_.RestAxisRotation(actuator)),
                      mechanism_.RestLength(actuator), actuator.head,
                      on_head ? actuator.anchor.index : -1,
                      mechanism_.AnchorRestPosition(actuator)});
  }
}

Eigen::Vector2d EquilibriumProblem::LocalVector(
    const Link& link, const Eigen::VectorXd& x) const {
  Eigen::Vector2d head =
      mechanism_.heads[link.head].rest_mm + x.segment<2>(2 * link.head);
  Eigen::Vector2d anchor = link.anchor_rest_mm;
  if (link.anchor_head >= 0) anchor += x.segment<2>(2 * link.anchor_head);
  return link.world_from_local.transpose() * (head - anchor);  // v = R^T(h-a)
}

bool EquilibriumProblem::Evaluate(const Eigen::VectorXd& pressures_mpa,
                                  const Eigen::VectorXd& x,
                                  Eigen::VectorXd* residual_n,
                                  Eigen::MatrixXd* jacobian_x,
                                  Eigen::MatrixXd* jacobian_pressure) const {
  const int n = NumUnknowns();
  assert(x.size() == n && pressures_mpa.size() == NumActuators());
  residual_n->setZero(n);
  if (jacobian_x) jacobian_x->setZero(n, n);
  if (jacobian_pressure) jacobian_pressure->setZero(n, NumActuators());

  // Written out in scalars in the world frame: this loop is the cost of every
  // Newton iteration and every workspace point.
  for (int k = 0; k < static_cast<int>(links_.size()); ++k) {
    const Link& link = links_[k];
    const int h = 2 * link.head;
    const int a = 2 * link.anchor_head;
    // w = h - a in the world frame; v = R^T w in the local frame.
    double wy = mechanism_.heads[link.head].rest_mm.x() + x[h] -
                link.anchor_rest_mm.x();
    double wz = mechanism_.heads[link.head].rest_mm.y() + x[h + 1] -
                link.anchor_rest_mm.y();
    if (link.anchor_head >= 0) {
      wy -= x[a];
      wz -= x[a + 1];
    }
    const double c = link.world_from_local(0, 0);  // R = [[c, -s], [s, c]]
    const double s = link.world_from_local(1, 0);
    const double vy = c * wy + s * wz;
    const double vz = -s * wy + c * wz;
    const double length_sq = wy * wy + wz * wz;
    const double length = std::sqrt(length_sq);
    if (!(length > 1e-9 * link.rest_length_mm)) return false;
    // dL and theta as defined in model.md ("One actuator").
    const Deformation deformation{length - link.rest_length_mm,
                                  std::atan2(-vy, vz)};
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
      // dF_world/dh = R (dF/d(dL) d(dL)/dv^T + dF/dtheta d(theta)/dv^T) R^T
      //             = (R dF/d(dL)) u^T + (R dF/dtheta) (perp(w) / |w|^2)^T,
      // since d(dL)/dv = v/|v| maps to u = w/|w|, d(theta)/dv =
      // (-v_z, v_y)/|v|^2 maps to perp(w) = (-w_z, w_y), and R commutes with
      // the quarter turn.
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
      if (link.anchor_head >= 0) {
        j(h, a) -= g00, j(h, a + 1) -= g01, j(h + 1, a) -= g10,
            j(h + 1, a + 1) -= g11;
        j(a, h) -= g00, j(a, h + 1) -= g01, j(a + 1, h) -= g10,
            j(a + 1, h + 1) -= g11;
        j(a, a) += g00, j(a, a + 1) += g01, j(a + 1, a) += g10,
            j(a + 1, a + 1) += g11;
      }
    }
    if (jacobian_pressure) {
      const Eigen::Vector2d& dp = force.d_force_d_pressure;
      const double py = c * dp.x() - s * dp.y(), pz = s * dp.x() + c * dp.y();
      (*jacobian_pressure)(h, k) += py;
      (*jacobian_pressure)(h + 1, k) += pz;
      if (link.anchor_head >= 0) {
        (*jacobian_pressure)(a, k) -= py;
        (*jacobian_pressure)(a + 1, k) -= pz;
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

std::optional<std::string> EquilibriumOptions::Check() const {
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
      lu_(problem.NumUnknowns()) {
  assert(!options_.Check());
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
  if (!has_solution_) return;
  // The net force is linear in P, so at the last solution
  //   R(x + dx, P + dP) ~ J dx + dR/dP dP = 0.
  SolveLinear(jacobian_, jacobian_pressure_ * (pressures_mpa - last_pressures_),
              &lu_, &step_);
  if (step_.allFinite()) *x -= step_;
}

EquilibriumSummary EquilibriumSolver::Solve(
    const Eigen::VectorXd& pressures_mpa, Eigen::VectorXd* x) {
  EquilibriumSummary summary;
  has_solution_ = false;
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
      has_solution_ = true;
      last_pressures_ = pressures_mpa;
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
