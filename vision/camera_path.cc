#include "vision/camera_path.h"

#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "util/check.h"

namespace softbench {

std::optional<std::string> CameraPathOptions::Check() const {
  if (!(step_px > 0.0)) return "step_px must be > 0";
  if (step_frames < 2) return "step_frames must be >= 2";
  if (transition_frames < 0) return "transition_frames must be >= 0";
  if (!(half_window_s >= 0.0)) return "half_window_s must be >= 0";
  return std::nullopt;
}

namespace {

double MedianOf(std::vector<double> v) {
  const size_t n = v.size();
  std::nth_element(v.begin(), v.begin() + n / 2, v.end());
  const double upper = v[n / 2];
  if (n % 2 == 1) return upper;
  return 0.5 * (upper + *std::max_element(v.begin(), v.begin() + n / 2));
}

Eigen::Vector4d Parameters(const CameraMotion& m) {
  return {m.rotation_rad.x(), m.rotation_rad.y(), m.rotation_rad.z(),
          std::log(m.scale)};
}

// The frames of one stretch (indices into the video's) where a step lies
// before them: a shift that changes by more than step_px between the
// medians of the step_frames before and after, largest within step_frames.
// A knock turns a tripod head and shifts the image; the roll alone is too
// noisy to find steps in.
std::vector<int> FindSteps(const CameraIntrinsics& k,
                           const std::vector<CameraMotion>& raw,
                           const std::vector<int>& frames,
                           const CameraPathOptions& options) {
  const int n = static_cast<int>(frames.size()), w = options.step_frames;
  std::vector<Eigen::Vector2d> shift(n);
  for (int i = 0; i < n; ++i) shift[i] = raw[frames[i]].ShiftPx(k);
  std::vector<double> score(n, 0.0);
  for (int i = w; i + w <= n; ++i) {
    for (int c = 0; c < 2; ++c) {
      std::vector<double> before, after;
      for (int j = i - w; j < i; ++j) before.push_back(shift[j][c]);
      for (int j = i; j < i + w; ++j) after.push_back(shift[j][c]);
      score[i] =
          std::max(score[i], std::abs(MedianOf(after) - MedianOf(before)));
    }
  }
  std::vector<int> steps;
  for (int i = 0; i < n; ++i) {
    if (score[i] <= options.step_px) continue;
    bool largest = true;
    for (int j = std::max(0, i - w); j < std::min(n, i + w + 1); ++j) {
      largest &= score[j] < score[i] || (score[j] == score[i] && j >= i);
    }
    if (largest) steps.push_back(i);
  }
  return steps;
}

void SmoothStretch(const CameraIntrinsics& k, const std::vector<double>& t,
                   const std::vector<CameraMotion>& raw,
                   const std::vector<int>& frames,
                   const CameraPathOptions& options,
                   std::vector<CameraMotion>* out) {
  const int n = static_cast<int>(frames.size());
  std::vector<int> segment(n, 0);
  std::vector<bool> transition(n, false);
  const std::vector<int> steps = FindSteps(k, raw, frames, options);
  for (size_t s = 0; s < steps.size(); ++s) {
    for (int i = steps[s]; i < n; ++i) segment[i] = static_cast<int>(s) + 1;
    for (int i = std::max(0, steps[s] - options.transition_frames);
         i < std::min(n, steps[s] + options.transition_frames); ++i) {
      transition[i] = true;
    }
  }
  for (int i = 0; i < n; ++i) {
    if (transition[i]) continue;
    // A straight line through the stretch's frames within the half window,
    // read at this frame: a tripod's drift is a slope, which a running mean
    // or median would drag behind near a knock (a one-sided window).
    Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
    Eigen::Matrix<double, 2, 4> rhs = Eigen::Matrix<double, 2, 4>::Zero();
    // Frames are in time order: only the half window's are visited.
    int first = i, last = i;
    while (first > 0 &&
           t[frames[i]] - t[frames[first - 1]] <= options.half_window_s) {
      --first;
    }
    while (last + 1 < n &&
           t[frames[last + 1]] - t[frames[i]] <= options.half_window_s) {
      ++last;
    }
    for (int j = first; j <= last; ++j) {
      const double dt = t[frames[j]] - t[frames[i]];
      if (segment[j] != segment[i] || transition[j]) continue;
      const Eigen::Vector2d a(1.0, dt);
      normal += a * a.transpose();
      rhs += a * Parameters(raw[frames[j]]).transpose();
    }
    // With one frame, or all at one time, the line is its mean.
    const Eigen::Vector4d p =
        std::abs(normal.determinant()) > 1e-12 * normal(0, 0) * normal(0, 0)
            ? Eigen::Vector4d((normal.inverse() * rhs).row(0).transpose())
            : Eigen::Vector4d(rhs.row(0).transpose() / normal(0, 0));
    CameraMotion& m = (*out)[frames[i]];
    m.rotation_rad = p.head<3>();
    m.scale = std::exp(p[3]);
  }
}

}  // namespace

std::vector<CameraMotion> SmoothCameraPath(const CameraIntrinsics& intrinsics,
                                           const std::vector<double>& times_s,
                                           const std::vector<CameraMotion>& raw,
                                           const std::vector<bool>& valid,
                                           double max_gap_s,
                                           const CameraPathOptions& options) {
  SOFTBENCH_CHECK(!options.Check()) << *options.Check();
  std::vector<CameraMotion> out = raw;
  std::vector<int> stretch;
  const auto flush = [&] {
    if (!stretch.empty()) {
      SmoothStretch(intrinsics, times_s, raw, stretch, options, &out);
    }
    stretch.clear();
  };
  for (size_t i = 0; i < raw.size(); ++i) {
    if (!valid[i]) continue;
    if (!stretch.empty() && times_s[i] - times_s[stretch.back()] > max_gap_s) {
      flush();
    }
    stretch.push_back(static_cast<int>(i));
  }
  flush();
  return out;
}

}  // namespace softbench
