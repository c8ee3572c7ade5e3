#include "pipelines/measurement/snapshots.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <utility>

namespace softbench {

namespace {

// The item nearest `time_s` of items in time order (frames or snapshots),
// or null when there are none.
template <typename T>
const T* NearestInTime(const std::vector<T>& items, double time_s) {
  const auto it =
      std::lower_bound(items.begin(), items.end(), time_s,
                       [](const T& item, double t) { return item.time_s < t; });
  const T* nearest = nullptr;
  if (it != items.end()) nearest = &*it;
  if (it != items.begin() &&
      (nearest == nullptr ||
       time_s - std::prev(it)->time_s < nearest->time_s - time_s)) {
    nearest = &*std::prev(it);
  }
  return nearest;
}

}  // namespace

const FrameSample* FindFrame(const VideoMeasurement& measurement,
                             double time_s) {
  const FrameSample* nearest = NearestInTime(measurement.frames, time_s);
  return nearest != nullptr && std::abs(nearest->time_s - time_s) <=
                                   measurement.frame_interval_s + 1e-9
             ? nearest
             : nullptr;
}

FrameSnapshot SnapshotHeads(const FrameSource& frame, const FrameSample& sample,
                            const TestPlan& plan, double mm_per_px,
                            double requested_s) {
  FrameSnapshot snapshot;
  snapshot.requested_s = requested_s;
  snapshot.frame = sample.frame;
  snapshot.time_s = sample.time_s;
  for (size_t h = 0; h < sample.heads.size(); ++h) {
    const HeadObservation& obs = sample.heads[h].observation;
    HeadCrop& crop = snapshot.heads.emplace_back();
    std::vector<Eigen::Vector2d> dots;
    for (const DotObservation& dot : obs.dots) {
      if (dot.found) dots.push_back(dot.pixel);
    }
    const cv::Rect box = BoxAround(
        dots, 2.5 * plan.markers[h].dot_diameter_mm / std::max(mm_per_px, 1e-9),
        frame.luma().size());
    if (box.empty()) continue;
    crop.bgr = frame.BgrRegion(box);
    crop.origin_px = Eigen::Vector2d(box.x, box.y);
  }
  return snapshot;
}

void CaptureSnapshots(const TestPlan& plan, const std::vector<double>& times_s,
                      double max_offset_s, VideoReader* reader,
                      VideoMeasurement* measurement) {
  std::vector<double> times = times_s;
  std::sort(times.begin(), times.end());
  const std::vector<FrameSnapshot> kept =
      std::exchange(measurement->window_frames, {});
  for (double t : times) {
    const FrameSample* sample = FindFrame(*measurement, t);
    if (sample == nullptr) continue;  // not measured: nothing to annotate
    const FrameSnapshot* nearest = NearestInTime(kept, t);
    if (nearest != nullptr && std::abs(nearest->time_s - t) <= max_offset_s) {
      measurement->snapshots.push_back(*nearest);
      measurement->snapshots.back().requested_s = t;
      continue;
    }
    const VideoFrame frame = reader->SeekTo(sample->time_s);
    measurement->snapshots.push_back(
        SnapshotHeads(VideoFrameSource(reader, &frame), *sample, plan,
                      measurement->mm_per_px, t));
  }
}

}  // namespace softbench
