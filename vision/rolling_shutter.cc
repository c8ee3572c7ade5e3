#include "vision/rolling_shutter.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "util/check.h"

namespace softbench {

std::optional<std::string> RollingShutterOptions::Problem() const {
  if (velocity_half_frames < 1) return "velocity_half_frames must be >= 1";
  if (block_frames < 1) return "block_frames must be >= 1";
  if (min_blocks < 2) return "min_blocks must be >= 2";
  if (!(max_standard_error_s > 0.0)) {
    return "max_standard_error_s must be > 0";
  }
  if (!(systematic_s >= 0.0)) return "systematic_s must be >= 0";
  if (!(min_significance > 0.0)) return "min_significance must be > 0";
  return std::nullopt;
}

namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Design = Eigen::Matrix<double, 4, 6>;

// The differentiator's weights h_n, n = 1..half: v = sum h_n (x[i+n] -
// x[i-n]) / dt. The ideal differentiator's (-1)^(n+1) / n under a Hann
// window, scaled so a straight line's slope comes out exact.
std::vector<double> DifferentiatorWeights(int half) {
  std::vector<double> h(half + 1, 0.0);
  double slope = 0.0;
  for (int n = 1; n <= half; ++n) {
    const double window =
        0.5 + 0.5 * std::cos(std::numbers::pi * n / (half + 1));
    h[n] = window * (n % 2 == 1 ? 1.0 : -1.0) / n;
    slope += 2.0 * n * h[n];
  }
  for (double& w : h) w /= slope;
  return h;
}

// The frame's design: its four sums' coefficients from the common pattern
// (the first four parameters) and the two readouts.
Design DesignOf(const Eigen::Vector2d& v) {
  Design m = Design::Zero();
  m.leftCols<4>().setIdentity();
  m.block<2, 1>(0, 4) = v;
  m.block<2, 1>(2, 5) = v;
  return m;
}

// The inverse of a symmetric positive semi-definite matrix on the
// directions whose eigenvalues reach 1e-6 of the largest; zero on the
// others.
Eigen::Matrix4d PseudoInverse(const Eigen::Matrix4d& m) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eigen(m);
  const Eigen::Vector4d& values = eigen.eigenvalues();
  Eigen::Vector4d inverted = Eigen::Vector4d::Zero();
  for (int k = 0; k < 4; ++k) {
    if (values[k] > 1e-6 * values.maxCoeff()) inverted[k] = 1.0 / values[k];
  }
  return eigen.eigenvectors() * inverted.asDiagonal() *
         eigen.eigenvectors().transpose();
}

const char* Direction(bool rows, double readout_s) {
  if (rows) return readout_s >= 0 ? "top row first" : "bottom row first";
  return readout_s >= 0 ? "left column first" : "right column first";
}

// The two readouts fitted by weighted least squares of the sums of the
// `known` frames whose velocity is known on their designs, with their
// covariance; nullopt when the frames carry no information on them.
struct ReadoutFit {
  Eigen::Vector2d readouts_s;  // along the rows, the columns
  Eigen::Matrix2d covariance;  // the sandwich's, over `blocks` blocks
};
std::optional<ReadoutFit> FitReadouts(
    const std::vector<ShutterShearSums>& sums,
    const std::vector<std::optional<Eigen::Vector2d>>& velocities, int known,
    int blocks, const RollingShutterOptions& options) {
  // Weighted least squares of every frame's sums on its design.
  Matrix6d a = Matrix6d::Zero();
  Vector6d b = Vector6d::Zero();
  for (size_t i = 0; i < sums.size(); ++i) {
    if (!velocities[i]) continue;
    const Design m = DesignOf(*velocities[i]);
    a += m.transpose() * sums[i].basis_gram * m;
    b += m.transpose() * sums[i].misfit_dot_basis;
  }
  // The common pattern is profiled out: of its four bases, the fitted roll
  // takes up nearly all of the difference of the two shears and the fitted
  // scale of the sum of the two stretches, so only its well-measured
  // directions are kept (a pseudo-inverse).
  const Eigen::Matrix4d common_inverse = PseudoInverse(a.topLeftCorner<4, 4>());
  const Eigen::Matrix<double, 2, 4> cross = a.bottomLeftCorner<2, 4>();
  const Eigen::Matrix2d information =
      a.bottomRightCorner<2, 2>() - cross * common_inverse * cross.transpose();
  const Eigen::Vector2d readouts_b =
      b.tail<2>() - cross * common_inverse * b.head<4>();
  // A still camera leaves no information on the readouts.
  if (!(information.determinant() > 0.0 && information(0, 0) > 0.0)) {
    return std::nullopt;
  }
  const Eigen::Matrix2d information_inverse = information.inverse();
  Vector6d theta;
  theta.tail<2>() = information_inverse * readouts_b;
  theta.head<4>() =
      common_inverse * (b.head<4>() - cross.transpose() * theta.tail<2>());
  // Standard errors by the sandwich over blocks of frames: the scatter of
  // the blocks' scores, whatever the misfits' noise and correlations.
  Eigen::Matrix2d meat = Eigen::Matrix2d::Zero();
  Vector6d score = Vector6d::Zero();
  int k = 0;  // frames scored so far
  for (size_t i = 0; i < sums.size(); ++i) {
    if (!velocities[i]) continue;
    const Design m = DesignOf(*velocities[i]);
    const ShutterShearSums& s = sums[i];
    score += m.transpose() * (s.misfit_dot_basis - s.basis_gram * m * theta);
    ++k;
    const bool block_ends =
        k % options.block_frames == 0 && k / options.block_frames < blocks;
    if (block_ends || k == known) {
      const Eigen::Vector2d z =
          score.tail<2>() - cross * common_inverse * score.head<4>();
      meat += z * z.transpose();
      score.setZero();
    }
  }
  return ReadoutFit{theta.tail<2>(), information_inverse * meat *
                                         information_inverse *
                                         (blocks / (blocks - 1.0))};
}

}  // namespace

double RollingShutter::ReadDelayS(const Eigen::Vector2d& pixel,
                                  const Eigen::Vector2d& frame_size_px) const {
  if (!seen) return 0.0;
  const int axis = by_rows ? 1 : 0;
  return readout_s() * ((pixel[axis] + 0.5) / frame_size_px[axis] - 0.5);
}

CameraMotion RollingShutter::MiddleLineMotion(
    const CameraMotion& fitted, const ShutterShearSums& sums,
    const Eigen::Vector2d& velocity_px_s) const {
  if (!seen) return fitted;
  // The shear's coefficients on the four bases, and what the fit took up
  // of them.
  Eigen::Vector4d coefficients = Eigen::Vector4d::Zero();
  coefficients.segment<2>(by_rows ? 0 : 2) = readout_s() * velocity_px_s;
  const Eigen::Vector4d taken = sums.motion_from_basis * coefficients;
  CameraMotion middle = fitted;
  middle.rotation_rad -= taken.head<3>();
  middle.scale *= std::exp(-taken[3]);
  return middle;
}

std::vector<std::optional<Eigen::Vector2d>> ImageVelocities(
    const RegisteredFrames& frames, const RollingShutterOptions& options) {
  const std::vector<double>& times_s = frames.times_s;
  const std::vector<Eigen::Vector2d>& shifts_px = frames.shifts_px;
  const std::vector<int64_t>& frame_index = frames.index;
  const std::vector<bool>& registered = frames.registered;
  const int n = static_cast<int>(times_s.size());
  SOFTBENCH_CHECK(static_cast<int>(shifts_px.size()) == n &&
                  static_cast<int>(frame_index.size()) == n &&
                  static_cast<int>(registered.size()) == n)
      << "one time, shift, index and flag per frame";
  const int half = options.velocity_half_frames;
  const std::vector<double> h = DifferentiatorWeights(half);
  std::vector<std::optional<Eigen::Vector2d>> velocities(n);
  for (int i = half; i + half < n; ++i) {
    const double dt = (times_s[i + half] - times_s[i - half]) / (2.0 * half);
    if (!(dt > 0.0)) continue;
    bool even = true;
    for (int j = i - half; j <= i + half && even; ++j) {
      even = registered[j] &&
             (j == i - half ||
              (frame_index[j] == frame_index[j - 1] + 1 &&
               std::abs(times_s[j] - times_s[j - 1] - dt) <= 0.25 * dt));
    }
    if (!even) continue;
    Eigen::Vector2d v = Eigen::Vector2d::Zero();
    for (int k = 1; k <= half; ++k) {
      v += h[k] * (shifts_px[i + k] - shifts_px[i - k]);
    }
    velocities[i] = v / dt;
  }
  return velocities;
}

std::string RollingShutter::Summary() const {
  if (!measured) return "not measured: " + why_not;
  if (!seen) {
    return fmt::format(
        "none seen over {} frames (a readout of {:+.1f} ± {:.1f} ms along "
        "the rows, {:+.1f} ± {:.1f} ms along the columns)",
        frames, 1e3 * rows_readout_s, 1e3 * rows_standard_error_s,
        1e3 * columns_readout_s, 1e3 * columns_standard_error_s);
  }
  return fmt::format(
      "lines read over {:.1f} ± {:.1f} ms, {}, over {} frames: the image "
      "moved {:.3f} px RMS between the first line read and the last",
      1e3 * std::abs(readout_s()), 1e3 * standard_error_s(),
      Direction(by_rows, readout_s()), frames, shear_rms_px);
}

RollingShutter EstimateRollingShutter(
    const RegisteredFrames& frames,
    const std::vector<std::optional<Eigen::Vector2d>>& velocities,
    const RollingShutterOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  const size_t n = frames.times_s.size();
  SOFTBENCH_CHECK(frames.sums.size() == n && velocities.size() == n)
      << "one sum and one velocity per frame";
  RollingShutter out;
  out.frames = static_cast<int>(
      std::count_if(velocities.begin(), velocities.end(),
                    [](const auto& v) { return v.has_value(); }));
  const int blocks = out.frames / options.block_frames;
  if (blocks < options.min_blocks) {
    out.why_not = fmt::format(
        "{} frames have {} registered, evenly spaced frames either side to "
        "give the camera's velocity ({} needed)",
        out.frames, options.velocity_half_frames,
        options.min_blocks * options.block_frames);
    return out;
  }
  const std::optional<ReadoutFit> fit =
      FitReadouts(frames.sums, velocities, out.frames, blocks, options);
  if (!fit) {
    out.why_not = fmt::format(
        "the camera did not move over {} frames, and a still image shows no "
        "rolling shutter's shear",
        out.frames);
    return out;
  }
  const Eigen::Matrix2d& covariance = fit->covariance;
  out.rows_readout_s = fit->readouts_s[0];
  out.columns_readout_s = fit->readouts_s[1];
  const double systematic = options.systematic_s * options.systematic_s;
  out.rows_standard_error_s = std::sqrt(covariance(0, 0) + systematic);
  out.columns_standard_error_s = std::sqrt(covariance(1, 1) + systematic);
  out.by_rows = std::abs(out.rows_readout_s) * out.columns_standard_error_s >=
                std::abs(out.columns_readout_s) * out.rows_standard_error_s;
  if (!(out.standard_error_s() <= options.max_standard_error_s)) {
    out.why_not = fmt::format(
        "the camera moved too little over {} frames to show a rolling "
        "shutter's shear (its readout would be known to ± {:.1f} ms)",
        out.frames, 1e3 * out.standard_error_s());
    return out;
  }
  out.measured = true;
  const double readout_s = out.readout_s();
  out.seen =
      std::abs(readout_s) >= options.min_significance * out.standard_error_s();
  double squares = 0.0;
  for (const std::optional<Eigen::Vector2d>& v : velocities) {
    if (v) squares += (readout_s * *v).squaredNorm();
  }
  out.shear_rms_px = std::sqrt(squares / out.frames);
  return out;
}

}  // namespace softbench
