#include "vision/plate_pose.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

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

struct DotResidual {
  template <typename T>
  bool operator()(const T* pose, T* residual) const {
    T seen[2];
    Apparent(pose, local, camera, seen);
    residual[0] = (seen[0] - observed.x()) / sigma_mm;
    residual[1] = (seen[1] - observed.y()) / sigma_mm;
    return true;
  }
  Eigen::Vector2d local, observed;
  CameraAbovePlane camera;
  double sigma_mm;
};

struct TiltPrior {
  template <typename T>
  bool operator()(const T* pose, T* residual) const {
    residual[0] = pose[3] / sigma_rad;
    residual[1] = pose[4] / sigma_rad;
    return true;
  }
  double sigma_rad;
};

Eigen::Vector2d Mean(const std::vector<Eigen::Vector2d>& points) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : points) sum += p;
  return sum / static_cast<double>(points.size());
}

}  // namespace

std::optional<std::string> PlatePoseOptions::Problem() const {
  if (!(dot_sigma_mm > 0.0)) return "dot_sigma_mm must be > 0";
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
                       const CameraAbovePlane& camera,
                       const PlatePoseOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  SOFTBENCH_CHECK(rest_dots_mm.size() == dots_mm.size() && dots_mm.size() >= 2)
      << "a plate's pose needs the same two or more dots at rest and now";
  SOFTBENCH_CHECK(camera.height_mm > 0.0) << "the camera must be above";
  const Eigen::Vector2d rest_centre = Mean(rest_dots_mm);
  const Eigen::Vector2d centre = Mean(dots_mm);
  // Start flat at the apparent centre, turned as the dots' first pair.
  const Eigen::Vector2d a = rest_dots_mm[1] - rest_dots_mm[0];
  const Eigen::Vector2d b = dots_mm[1] - dots_mm[0];
  double pose[kPoseSize] = {
      centre.x(), centre.y(),
      0.0,        0.0,
      0.0,        std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b))};
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  for (size_t i = 0; i < dots_mm.size(); ++i) {
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<DotResidual, 2, kPoseSize>(
            new DotResidual{rest_dots_mm[i] - rest_centre, dots_mm[i], camera,
                            options.dot_sigma_mm}),
        nullptr, pose);
  }
  problem.AddResidualBlock(
      new ceres::AutoDiffCostFunction<TiltPrior, 2, kPoseSize>(
          new TiltPrior{options.tilt_prior_rad}),
      nullptr, pose);
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = options.max_iterations;
  // Tight enough for a lift to a micrometre; near the camera's axis the
  // tilt enters to second order and convergence there is linear, so the
  // cost's relative change is what stops it.
  solver.function_tolerance = 1e-10;
  solver.gradient_tolerance = 1e-12;
  solver.parameter_tolerance = 1e-10;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);

  PlatePose out;
  out.found = summary.IsSolutionUsable();
  if (!out.found) out.why_not = summary.message;
  out.centre_mm = Eigen::Vector2d(pose[0], pose[1]);
  out.lift_mm = pose[2];
  out.tilt_rad = Eigen::Vector2d(pose[3], pose[4]);
  out.rotation_rad = pose[5];
  out.parallax_mm = centre - out.centre_mm;
  return out;
}

}  // namespace softbench
