#ifndef SOFTBENCH_PIPELINES_MEASUREMENT_SPAN_MEASURER_H_
#define SOFTBENCH_PIPELINES_MEASUREMENT_SPAN_MEASURER_H_

#include <fmt/format.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <functional>
#include <iterator>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "pipelines/formats/test_plan.h"
#include "pipelines/measurement/snapshots.h"
#include "pipelines/measurement/video_measurement.h"
#include "pipelines/measurement/window_frames.h"
#include "util/input_error.h"
#include "vision/bench_registration.h"
#include "vision/frame_source.h"
#include "vision/head_tracker.h"
#include "vision/video_reader.h"

namespace softbench {

// A time a snapshot was asked for, and the time of its nearest frame.
struct SnapshotTime {
  double requested_s, frame_s;
};

// What every frame is registered to, from the video's first frame: its tag
// (the corners of the mapping, re-located in that frame) and where its
// static patches may be taken. The frame itself is not kept: the patches
// copy what they need of it.
struct RegistrationReference {
  cv::Mat static_mask;
  std::optional<TagReference> tag;
};

// The reference from the video's first frame (`first`), through the plan's
// mapping and, when the plan has a tag, the tag's corners.
RegistrationReference MakeRegistrationReference(
    const TestPlan& plan, const FrameSource& first, const PlaneMapping& mapping,
    const std::optional<std::array<Eigen::Vector2d, 4>>& tag_corners);

// A head observation for a frame that could not be measured at all.
HeadObservation Unmeasured(int dots, const std::string& why);

// Measures spans of a video with one reader and one tracker, keeping the
// frames, the snapshots asked for and the counts.
class SpanMeasurer {
 public:
  // `reader` (luma, not BGR) is not owned. `registration`, when given,
  // registers every frame to the bench before its heads are measured,
  // through `mapping` after the camera's motion.
  SpanMeasurer(const TestPlan& plan, VideoReader* reader, PlaneMapping mapping,
               double mm_per_px, HeadTracker tracker,
               std::unique_ptr<BenchRegistration> registration,
               const std::vector<SnapshotTime>& snapshot_times,
               std::atomic<int64_t>* frames_done)
      : plan_(&plan),
        mapping_(std::move(mapping)),
        registration_(std::move(registration)),
        mm_per_px_(mm_per_px),
        reader_(reader),
        tracker_(std::move(tracker)),
        snapshot_times_(&snapshot_times),
        frames_done_(frames_done) {}

  const HeadTracker& tracker() const { return tracker_; }
  const std::string& path() const { return reader_->path(); }
  int patch_count() const {
    return registration_ ? registration_->patch_count() : 0;
  }
  // Throw InputError when the first frame measured lacks a dot: it is the
  // heads' reference.
  void RequireCompleteFirstFrame() { first_frame_complete_ = true; }
  // Keep the crops that may turn out to be the windows' middles
  // (window_frames.h), for a run through every frame.
  void KeepWindowFrames(const WindowFrameKeeperOptions& options) {
    window_frames_.emplace(options);
  }

  // How a span's first frame is found.
  enum class Start {
    kSeek,    // a seek to the span's start
    kSought,  // `current`: what the reader's seek to the span's start gave
    kReadOn,  // the next frame from the reader's position
    kCurrent  // the frame the reader returned last (`current`)
  };
  // The frames of `span`; `poll` is called after each frame. After a seek
  // the heads are found again and the registration starts afresh, so what
  // a span measures does not depend on the spans measured before it.
  void Measure(const TimeSpan& span, Start start, const VideoFrame* current,
               const std::function<void()>& poll) {
    VideoFrame frame;
    if (start == Start::kSeek || start == Start::kSought) {
      frame = start == Start::kSeek ? reader_->SeekTo(span.start_s) : *current;
      tracker_.ForgetPositions();
      if (registration_ != nullptr) registration_->Restart();
    } else if (start == Start::kCurrent) {
      frame = *current;
    } else if (!reader_->Read(&frame)) {
      return;
    }
    // Snapshots are kept at their nearest frames' exact times.
    constexpr double kSameFrameS = 1e-6;
    auto next_snapshot = std::lower_bound(
        snapshot_times_->begin(), snapshot_times_->end(),
        frame.time_s - kSameFrameS,
        [](const SnapshotTime& s, double t) { return s.frame_s < t; });
    do {
      if (frame.time_s >= span.end_s) break;
      const VideoFrameSource source(reader_, &frame);
      FrameSample sample;
      sample.frame = frame.index;
      sample.time_s = frame.time_s;
      sample.intra = frame.intra;
      if (frame.damaged) {  // concealed pixels are never measured
        sample.damaged = true;
        sample.registered = false;
        FillUnmeasured("damaged video data", &sample);
        ++damaged_frames_;
        frames_.push_back(std::move(sample));
        ++*frames_done_;
        poll();
        continue;
      }
      if (!Register(frame, &sample)) {
        frames_.push_back(std::move(sample));
        ++*frames_done_;
        poll();
        continue;
      }
      bool full = false;
      for (HeadObservation& obs : tracker_.Measure(source)) {
        if (first_frame_complete_ && frames_.empty() && !obs.complete) {
          throw InputError(fmt::format(
              "{}: first frame measured (t = {:.3f} s): {}", reader_->path(),
              frame.time_s,
              obs.note.empty() ? "not every dot was found" : obs.note));
        }
        missing_dots_ += static_cast<int>(obs.dots.size()) - obs.dots_found;
        rejected_blobs_ += obs.rejected_blobs;
        full = full || obs.full_frame;
        sample.heads.push_back({std::move(obs), {}, {}});
      }
      full_frame_frames_ += full;
      if (window_frames_) {
        window_frames_->Offer(sample, [&] {
          return SnapshotHeads(source, sample, *plan_, mm_per_px_,
                               sample.time_s);
        });
      }
      for (; next_snapshot != snapshot_times_->end() &&
             frame.time_s >= next_snapshot->frame_s - kSameFrameS;
           ++next_snapshot) {
        if (frame.time_s <= next_snapshot->frame_s + kSameFrameS) {
          snapshots_.push_back(SnapshotHeads(source, sample, *plan_, mm_per_px_,
                                             next_snapshot->requested_s));
        }
      }
      frames_.push_back(std::move(sample));
      ++*frames_done_;
      poll();
    } while (reader_->Read(&frame));
    if (window_frames_) window_frames_->Finish();
  }

  // When the first frame this measurer could not register was shown
  // (infinity: none).
  double first_unregistered_s() const { return first_unregistered_s_; }

  // Appends what was measured to `m`, whose reason for unregistered frames
  // is this measurer's only when it has none yet.
  void MoveInto(VideoMeasurement* m) {
    std::move(frames_.begin(), frames_.end(), std::back_inserter(m->frames));
    std::move(snapshots_.begin(), snapshots_.end(),
              std::back_inserter(m->snapshots));
    if (window_frames_) m->window_frames = window_frames_->TakeKept();
    m->missing_dots += missing_dots_;
    m->rejected_blobs += rejected_blobs_;
    m->full_frame_frames += full_frame_frames_;
    m->unregistered_frames += unregistered_frames_;
    m->damaged_frames += damaged_frames_;
    for (const VideoReader::DamagedFrame& d : reader_->damaged_frames()) {
      if (d.lost) m->lost_frame_times_s.push_back(d.time_s);
    }
    std::sort(m->lost_frame_times_s.begin(), m->lost_frame_times_s.end());
    if (m->unregistered_reason.empty()) {
      m->unregistered_reason = unregistered_reason_;
    }
  }

 private:
  // Registers the frame to the bench and gives the tracker the frame's
  // mapping; false (the sample filled with unmeasured heads) when the frame
  // cannot be registered.
  bool Register(const VideoFrame& frame, FrameSample* sample) {
    if (registration_ == nullptr) return true;
    const FrameRegistration r = registration_->Register(frame.luma);
    sample->registered = r.registered;
    if (!r.registered) {
      if (first_frame_complete_ && frames_.empty()) {
        throw InputError(fmt::format(
            "{}: first frame measured (t = {:.3f} s) cannot be registered to "
            "the bench: {}",
            reader_->path(), frame.time_s, r.why_not));
      }
      ++unregistered_frames_;
      if (unregistered_reason_.empty()) {
        unregistered_reason_ = r.why_not;
        first_unregistered_s_ = frame.time_s;
      }
      FillUnmeasured("frame not registered: " + r.why_not, sample);
      return false;
    }
    sample->camera_motion = r.motion;
    sample->tag_corners = r.tag_corners;
    sample->shear_sums = r.shear_sums;
    tracker_.SetMapping(
        mapping_.AfterCameraMotion(r.motion.CurrentFromReference()));
    return true;
  }

  // Every head of `sample` not measured, for `why`.
  void FillUnmeasured(const std::string& why, FrameSample* sample) const {
    for (const MarkerSpec& marker : plan_->markers) {
      sample->heads.push_back({Unmeasured(marker.dots, why),
                               Eigen::Vector2d::Constant(std::nan("")),
                               Eigen::Vector2d::Constant(std::nan(""))});
    }
  }

  const TestPlan* plan_;
  PlaneMapping mapping_;
  std::unique_ptr<BenchRegistration> registration_;
  double mm_per_px_;
  VideoReader* reader_;
  HeadTracker tracker_;
  const std::vector<SnapshotTime>* snapshot_times_;
  std::atomic<int64_t>* frames_done_;
  std::vector<FrameSample> frames_;
  std::vector<FrameSnapshot> snapshots_;
  int missing_dots_ = 0, rejected_blobs_ = 0, full_frame_frames_ = 0;
  int unregistered_frames_ = 0;
  int damaged_frames_ = 0;
  std::string unregistered_reason_;
  double first_unregistered_s_ = INFINITY;  // its spans are in time order
  bool first_frame_complete_ = false;
  std::optional<WindowFrameKeeper> window_frames_;
};

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_MEASUREMENT_SPAN_MEASURER_H_
