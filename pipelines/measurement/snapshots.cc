#include "pipelines/measurement/snapshots.h"

#include <algorithm>
#include <cmath>
#include <iterator>

namespace softbench {

const FrameSample* FindFrame(const VideoMeasurement& measurement,
                             double time_s) {
  const std::vector<FrameSample>& frames = measurement.frames;
  const auto it = std::lower_bound(
      frames.begin(), frames.end(), time_s,
      [](const FrameSample& f, double t) { return f.time_s < t; });
  const FrameSample* nearest = nullptr;
  if (it != frames.end()) nearest = &*it;
  if (it != frames.begin() &&
      (nearest == nullptr ||
       time_s - std::prev(it)->time_s < nearest->time_s - time_s)) {
    nearest = &*std::prev(it);
  }
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
                      VideoReader* reader, VideoMeasurement* measurement) {
  std::vector<double> times = times_s;
  std::sort(times.begin(), times.end());
  for (double t : times) {
    const FrameSample* sample = FindFrame(*measurement, t);
    if (sample == nullptr) continue;  // not measured: nothing to annotate
    const VideoFrame frame = reader->SeekTo(sample->time_s);
    measurement->snapshots.push_back(
        SnapshotHeads(VideoFrameSource(reader, &frame), *sample, plan,
                      measurement->mm_per_px, t));
  }
}

}  // namespace softbench
