#include "vision/camera_path.h"

#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "util/check.h"

namespace softbench {

std::optional<std::string> CameraPathOptions::Problem() const {
  if (!(step_px > 0.0)) return "step_px must be > 0";
  if (step_frames < 2) return "step_frames must be >= 2";
  if (transition_frames < 0) return "transition_frames must be >= 0";
  if (!(half_window_s >= 0.0)) return "half_window_s must be >= 0";
  if (!(tremor_px >= 0.0)) return "tremor_px must be >= 0";
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

// The frames (indices into the video's) where a step lies
// before them: a shift that changes by more than step_px between the
// medians of the step_frames before and after, largest within step_frames.
// A knock turns a tripod head and shifts the image; the roll alone is too
// noisy to find steps in. Steps at gaps (`gap_before`: a seek between
// windows) go to `at_gaps`, the others to `moving` (the camera moved while
// it was filmed).
void FindSteps(const CameraIntrinsics& k, const std::vector<CameraMotion>& raw,
               const std::vector<int>& frames,
               const std::vector<bool>& gap_before,
               const CameraPathOptions& options, std::vector<int>* at_gaps,
               std::vector<int>* moving) {
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
  // A knock during a seek: the frames either side of the gap (as many as
  // there are, up to step_frames) disagree.
  for (int i = 1; i < n; ++i) {
    if (!gap_before[i]) continue;
    for (int c = 0; c < 2; ++c) {
      std::vector<double> before, after;
      for (int j = std::max(0, i - w); j < i; ++j)
        before.push_back(shift[j][c]);
      for (int j = i; j < std::min(n, i + w); ++j) after.push_back(shift[j][c]);
      if (std::abs(MedianOf(after) - MedianOf(before)) > options.step_px) {
        at_gaps->push_back(i);
        break;
      }
    }
  }
  for (int i = 0; i < n; ++i) {
    if (score[i] <= options.step_px) continue;
    bool largest = true;
    for (int j = std::max(0, i - w); j < std::min(n, i + w + 1); ++j) {
      largest &= score[j] < score[i] || (score[j] == score[i] && j >= i);
    }
    // One found at a gap nearby already is this one.
    for (int g : *at_gaps) largest &= std::abs(g - i) > w;
    if (largest) moving->push_back(i);
  }
}

// The camera's tremor over the video: the robust scatter of its shift from
// one frame to the next (1.4826 times the median absolute deviation of the
// differences, over sqrt 2; the larger axis), from consecutive frames of one
// segment away from its knocks and gaps.
double Tremor(const CameraIntrinsics& k, const std::vector<CameraMotion>& raw,
              const std::vector<int>& frames,
              const std::vector<bool>& gap_before,
              const std::vector<int>& segment,
              const std::vector<bool>& transition) {
  std::array<std::vector<double>, 2> differences;
  for (size_t i = 0; i + 1 < frames.size(); ++i) {
    if (gap_before[i + 1] || segment[i] != segment[i + 1] || transition[i] ||
        transition[i + 1]) {
      continue;
    }
    const Eigen::Vector2d d =
        raw[frames[i + 1]].ShiftPx(k) - raw[frames[i]].ShiftPx(k);
    for (int c = 0; c < 2; ++c) differences[c].push_back(d[c]);
  }
  double tremor = 0.0;
  for (std::vector<double>& d : differences) {
    if (d.empty()) return 0.0;
    const double median = MedianOf(d);
    for (double& v : d) v = std::abs(v - median);
    tremor = std::max(tremor, 1.4826 * MedianOf(d) / std::sqrt(2.0));
  }
  return tremor;
}

// The path through the registered `frames` (indices into the video's, in
// time order; `gap_before[i]`: a seek or unregistered frames before frame i).
void SmoothPath(const CameraIntrinsics& k, const std::vector<double>& t,
                const std::vector<CameraMotion>& raw,
                const std::vector<int>& frames,
                const std::vector<bool>& gap_before,
                const CameraPathOptions& options,
                std::vector<CameraMotion>* out) {
  const int n = static_cast<int>(frames.size());
  std::vector<int> at_gaps, moving;
  FindSteps(k, raw, frames, gap_before, options, &at_gaps, &moving);
  // Segments between steps; the frames around a knock filmed (not one
  // during a seek) keep their own motion.
  std::vector<int> steps = at_gaps;
  steps.insert(steps.end(), moving.begin(), moving.end());
  std::sort(steps.begin(), steps.end());
  std::vector<int> segment(n, 0);
  for (size_t s = 0; s < steps.size(); ++s) {
    for (int i = steps[s]; i < n; ++i) segment[i] = static_cast<int>(s) + 1;
  }
  std::vector<bool> transition(n, false);
  for (int step : moving) {
    for (int i = std::max(0, step - options.transition_frames);
         i < std::min(n, step + options.transition_frames); ++i) {
      transition[i] = true;
    }
  }
  // A trembling camera keeps each frame's own motion: tremor is real motion
  // of the image, which the registration follows to about 0.01 px.
  if (Tremor(k, raw, frames, gap_before, segment, transition) >
      options.tremor_px) {
    return;
  }
  for (int i = 0; i < n; ++i) {
    if (transition[i]) continue;
    // A straight line through the segment's frames within the half window,
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
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  std::vector<CameraMotion> out = raw;
  std::vector<int> frames;
  std::vector<bool> gap_before;
  for (size_t i = 0; i < raw.size(); ++i) {
    if (!valid[i]) continue;
    gap_before.push_back(!frames.empty() &&
                         times_s[i] - times_s[frames.back()] > max_gap_s);
    frames.push_back(static_cast<int>(i));
  }
  if (!frames.empty()) {
    SmoothPath(intrinsics, times_s, raw, frames, gap_before, options, &out);
  }
  return out;
}

}  // namespace softbench
