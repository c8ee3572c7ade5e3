#include "pipelines/measurement/window_frames.h"

#include <algorithm>
#include <utility>

#include "util/check.h"

namespace softbench {
namespace {

// Where the heads first move, relative to a kept candidate, lies within
// this many strides of half a window: the window's end found afterwards
// (a tenth of the motion's level, test_point_detection.h) falls a few
// milliseconds after the first move beyond motion_mm, and one stride either way
// leaves a candidate within half a stride of every middle.
constexpr double kMarginStrides = 1.5;

// The bytes of a snapshot's crops.
double CropMb(const FrameSnapshot& snapshot) {
  double bytes = 0.0;
  for (const HeadCrop& crop : snapshot.heads) {
    bytes += static_cast<double>(crop.bgr.total() * crop.bgr.elemSize());
  }
  return bytes / (1024.0 * 1024.0);
}

}  // namespace

std::optional<std::string> WindowFrameKeeperOptions::Problem() const {
  if (!(window_s > 0.0)) return "window_s must be > 0";
  if (!(stride_s > 0.0 && stride_s <= 0.25 * window_s)) {
    return "stride_s must be in (0, window_s / 4]";
  }
  if (!(motion_mm > 0.0)) return "motion_mm must be > 0";
  if (!(max_kept_mb >= 0.0)) return "max_kept_mb must be >= 0";
  return std::nullopt;
}

WindowFrameKeeper::WindowFrameKeeper(const WindowFrameKeeperOptions& options)
    : options_(options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
}

void WindowFrameKeeper::Offer(const FrameSample& sample,
                              const std::function<FrameSnapshot()>& crop) {
  if (!sample.registered || sample.damaged || sample.heads.empty()) return;
  std::vector<Eigen::Vector2d> positions_mm;
  for (const HeadSample& head : sample.heads) {
    if (!head.observation.complete) return;  // no decision on a partial view
    positions_mm.push_back(head.observation.position_mm);
  }
  last_time_s_ = sample.time_s;
  const double half_window_s = 0.5 * options_.window_s;
  const double margin_s = kMarginStrides * options_.stride_s;
  for (auto it = pending_.begin(); it != pending_.end();) {
    const double age_s = sample.time_s - it->snapshot.time_s;
    bool moved = false;
    for (size_t h = 0; h < positions_mm.size(); ++h) {
      moved = moved || (positions_mm[h] - it->positions_mm[h]).norm() >
                           options_.motion_mm;
    }
    if (moved && age_s >= half_window_s - margin_s) Keep(&*it);
    if (moved || age_s > half_window_s + margin_s) {
      it = pending_.erase(it);
    } else {
      ++it;
    }
  }
  // Frame times, not indices: under a variable frame rate the stride is
  // still one of time. The small slack keeps 3 frames at 30 fps 0.1 s apart.
  constexpr double kSlackS = 1e-6;
  if (sample.time_s >= last_candidate_s_ + options_.stride_s - kSlackS) {
    last_candidate_s_ = sample.time_s;
    pending_.push_back({crop(), std::move(positions_mm)});
  }
}

void WindowFrameKeeper::Finish() {
  const double half_window_s = 0.5 * options_.window_s;
  const double margin_s = kMarginStrides * options_.stride_s;
  for (Candidate& candidate : pending_) {
    if (last_time_s_ - candidate.snapshot.time_s >= half_window_s - margin_s) {
      Keep(&candidate);
    }
  }
  pending_.clear();
}

std::vector<FrameSnapshot> WindowFrameKeeper::TakeKept() {
  // Kept when the heads first moved away from each, which need not be in
  // the candidates' order.
  std::sort(kept_.begin(), kept_.end(),
            [](const FrameSnapshot& a, const FrameSnapshot& b) {
              return a.time_s < b.time_s;
            });
  return std::exchange(kept_, {});
}

void WindowFrameKeeper::Keep(Candidate* candidate) {
  const double mb = CropMb(candidate->snapshot);
  if (kept_mb_ + mb > options_.max_kept_mb) return;
  kept_mb_ += mb;
  kept_.push_back(std::move(candidate->snapshot));
}

}  // namespace softbench
