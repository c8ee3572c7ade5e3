#include "vision/plate_pose.h"

#include <ceres/rotation.h>
#include <ceres/tiny_solver.h>
#include <ceres/tiny_solver_autodiff_function.h>

#include <cmath>

#include "util/check.h"

namespace softbench {
namespace {

// pose = (centre y, centre z, lift, tilt y, tilt z, rotation).
constexpr int kPoseSize = 6;

// Where a plate point at `local` from its centre (on the plate, flat at
// rest) appears through the plane's mapping: turned by the rotation vector
// (tilt y, tilt z, rotation) in (y, z, up), raised and moved, then seen
// from the camera's centre on the plane: foot + (p - foot) H / (H - h).
template <typename T>
void Apparent(const T* pose, const Eigen::Vector2d& local,
              const CameraAbovePlane& camera, T* seen) {
  const T rotation_vector[3] = {pose[3], pose[4], pose[5]};
  const T point[3] = {static_cast<T>(local.x()), static_cast<T>(local.y()),
                      static_cast<T>(0.0)};
  T turned[3];
  ceres::AngleAxisRotatePoint(rotation_vector, point, turned);
  const auto height = static_cast<T>(camera.height_mm);
  const T k = height / (height - (pose[2] + turned[2]));
  seen[0] = camera.foot_mm.x() + (pose[0] + turned[0] - camera.foot_mm.x()) * k;
  seen[1] = camera.foot_mm.y() + (pose[1] + turned[1] - camera.foot_mm.y()) * k;
}

// Every dot's misfit in units of its standard error, then the two tilts'
// prior: one small dense problem, solved by Ceres's TinySolver (no
// Problem to build, no heap per iteration: a Ceres Problem cost ten times
// the pose's arithmetic, run for every head in every frame).
struct PoseResiduals {
  template <typename T>
  bool operator()(const T* pose, T* residual) const {
    for (size_t i = 0; i < rest.size(); ++i) {
      T seen[2];
      Apparent(pose, rest[i] - rest_centre, camera, seen);
      residual[2 * i] = (seen[0] - observed[i].x()) / sigma_mm;
      residual[2 * i + 1] = (seen[1] - observed[i].y()) / sigma_mm;
    }
    residual[2 * rest.size()] = pose[3] / sigma_rad;
    residual[2 * rest.size() + 1] = pose[4] / sigma_rad;
    return true;
  }
  int NumResiduals() const { return static_cast<int>(2 * rest.size() + 2); }

  // The caller's dots, at rest and now, read in place.
  const std::vector<Eigen::Vector2d>& rest;
  const std::vector<Eigen::Vector2d>& observed;
  Eigen::Vector2d rest_centre;
  CameraAbovePlane camera;
  double sigma_mm, sigma_rad;
};

Eigen::Vector2d Mean(const std::vector<Eigen::Vector2d>& points) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : points) sum += p;
  return sum / static_cast<double>(points.size());
}

}  // namespace

std::optional<std::string> PlatePoseOptions::Problem() const {
  if (!(tilt_prior_rad > 0.0)) return "tilt_prior_rad must be > 0";
  if (max_iterations < 1) return "max_iterations must be >= 1";
  return std::nullopt;
}

std::vector<Eigen::Vector2d> ApparentDots(
    const std::vector<Eigen::Vector2d>& rest_dots_mm,
    const CameraAbovePlane& camera, const Eigen::Vector2d& centre_mm,
    double lift_mm, const Eigen::Vector2d& tilt_rad, double rotation_rad) {
  const Eigen::Vector2d rest_centre = Mean(rest_dots_mm);
  const double pose[kPoseSize] = {centre_mm.x(), centre_mm.y(), lift_mm,
                                  tilt_rad.x(),  tilt_rad.y(),  rotation_rad};
  std::vector<Eigen::Vector2d> seen(rest_dots_mm.size());
  for (size_t i = 0; i < rest_dots_mm.size(); ++i) {
    Apparent(pose, rest_dots_mm[i] - rest_centre, camera, seen[i].data());
  }
  return seen;
}

PlatePose FitPlatePose(const std::vector<Eigen::Vector2d>& rest_dots_mm,
                       const std::vector<Eigen::Vector2d>& dots_mm,
                       const CameraAbovePlane& camera, double dot_sigma_mm,
                       const PlatePoseOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  SOFTBENCH_CHECK(dot_sigma_mm > 0.0) << "a dot's sigma must be > 0";
  SOFTBENCH_CHECK(rest_dots_mm.size() == dots_mm.size() && dots_mm.size() >= 2)
      << "a plate's pose needs the same two or more dots at rest and now";
  SOFTBENCH_CHECK(camera.height_mm > 0.0) << "the camera must be above";
  const Eigen::Vector2d rest_centre = Mean(rest_dots_mm);
  const Eigen::Vector2d centre = Mean(dots_mm);
  // Start flat at the apparent centre, turned as the dots' first pair.
  const Eigen::Vector2d a = rest_dots_mm[1] - rest_dots_mm[0];
  const Eigen::Vector2d b = dots_mm[1] - dots_mm[0];
  Eigen::Matrix<double, kPoseSize, 1> pose;
  pose << centre.x(), centre.y(), 0.0, 0.0, 0.0,
      std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
  const PoseResiduals residuals{rest_dots_mm, dots_mm,
                                rest_centre,  camera,
                                dot_sigma_mm, options.tilt_prior_rad};
  using Function = ceres::TinySolverAutoDiffFunction<PoseResiduals,
                                                     Eigen::Dynamic, kPoseSize>;
  const Function function(residuals);
  ceres::TinySolver<Function> solver;
  solver.options.max_num_iterations = options.max_iterations;
  // Tight enough for a lift to a micrometre; near the camera's axis the
  // tilt enters to second order and convergence there is linear, so the
  // cost's change is what stops it (TinySolver's is absolute: the cost at
  // the minimum is about the number of dots, in their variances).
  solver.options.function_tolerance = 1e-10;
  solver.options.gradient_tolerance = 1e-12;
  solver.options.parameter_tolerance = 1e-10;
  const auto& summary = solver.Solve(function, &pose);

  PlatePose out;
  // TinySolver does not report failure: a pose that left the finite
  // numbers (a plate raised to the camera) is not usable.
  out.found = pose.allFinite() && std::isfinite(summary.final_cost);
  if (!out.found) out.why_not = "the pose's fit diverged";
  out.centre_mm = Eigen::Vector2d(pose[0], pose[1]);
  out.lift_mm = pose[2];
  out.tilt_rad = Eigen::Vector2d(pose[3], pose[4]);
  out.rotation_rad = pose[5];
  out.parallax_mm = centre - out.centre_mm;
  return out;
}

double LiftSigmaFromDots(const std::vector<Eigen::Vector2d>& rest_dots_mm,
                         const CameraAbovePlane& camera, double dot_sigma_mm,
                         double fit_dot_sigma_mm,
                         const PlatePoseOptions& options) {
  // Each coordinate of each dot a standard deviation either way; half the
  // lift's change is that coordinate's share (GUM's linear propagation, as
  // the intrinsics' term does it).
  double squares = 0.0;
  for (size_t i = 0; i < rest_dots_mm.size(); ++i) {
    for (int axis = 0; axis < 2; ++axis) {
      std::vector<Eigen::Vector2d> up = rest_dots_mm, down = rest_dots_mm;
      up[i][axis] += dot_sigma_mm;
      down[i][axis] -= dot_sigma_mm;
      const PlatePose a =
          FitPlatePose(rest_dots_mm, up, camera, fit_dot_sigma_mm, options);
      const PlatePose b =
          FitPlatePose(rest_dots_mm, down, camera, fit_dot_sigma_mm, options);
      if (!a.found || !b.found) return NAN;
      squares += std::pow(0.5 * (a.lift_mm - b.lift_mm), 2);
    }
  }
  return std::sqrt(squares);
}

}  // namespace softbench
