#ifndef SOFTBENCH_PIPELINES_MEASUREMENT_WINDOW_FRAMES_H_
#define SOFTBENCH_PIPELINES_MEASUREMENT_WINDOW_FRAMES_H_

#include <Eigen/Core>
#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "pipelines/measurement/frame_sample.h"

namespace softbench {

struct WindowFrameKeeperOptions {
  // The plan's window length [s]: every window ends where the heads start
  // to move (an actuation or a release) or at the video's end, so its
  // middle lies half a window before that.
  double window_s = 1.0;
  // At most one candidate per stride [s]; a window's middle is served by a
  // kept frame within this of it, else by a seek.
  double stride_s = 0.1;
  // A head farther than this from where it was in a candidate [mm] has
  // moved: far above tremor and codec noise after registration (about
  // 0.002 mm), below the 10 % crossing of any test's motion that matters.
  double motion_mm = 0.02;
  // The kept crops' memory bound [MB]: past it no more are kept, and the
  // windows left without one are served by seeks.
  double max_kept_mb = 64.0;

  std::optional<std::string> Problem() const;
};

// Keeps, on a run through every frame whose test times are not yet known
// (they are found from the motion afterwards), the head crops that may turn
// out to be a window's middle frame, so the report's pictures need no
// second decoding of the video (each seek decodes from the previous
// keyframe: on the delta sample, its 29 middles decoded a third of the
// video again). A candidate is cut every stride from frames with every head
// measured, and kept only when the heads first move about half a window
// after it: all the middles, at a few crops per window.
class WindowFrameKeeper {
 public:
  explicit WindowFrameKeeper(const WindowFrameKeeperOptions& options);

  // The next measured frame, in time order; `crop` cuts its heads out and
  // is called only when the frame becomes a candidate.
  void Offer(const FrameSample& sample,
             const std::function<FrameSnapshot()>& crop);
  // The video ended after the last frame offered (the last test's final
  // window ends there).
  void Finish();
  // The kept crops, in time order.
  std::vector<FrameSnapshot> TakeKept();

 private:
  struct Candidate {
    FrameSnapshot snapshot;
    std::vector<Eigen::Vector2d> positions_mm;
  };
  void Keep(Candidate* candidate);

  WindowFrameKeeperOptions options_;
  std::deque<Candidate> pending_;
  std::vector<FrameSnapshot> kept_;
  double last_candidate_s_ = -1e300;
  double last_time_s_ = -1e300;
  double kept_mb_ = 0.0;
};

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_MEASUREMENT_WINDOW_FRAMES_H_
