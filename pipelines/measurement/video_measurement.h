#ifndef SOFTBENCH_PIPELINES_MEASUREMENT_VIDEO_MEASUREMENT_H_
#define SOFTBENCH_PIPELINES_MEASUREMENT_VIDEO_MEASUREMENT_H_

#include <Eigen/Core>
#include <limits>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pipelines/formats/test_plan.h"
#include "pipelines/measurement/camera_processing.h"
#include "pipelines/measurement/frame_sample.h"
#include "pipelines/measurement/plan_camera.h"
#include "pipelines/measurement/window_frames.h"
#include "vision/bench_registration.h"
#include "vision/camera_path.h"
#include "vision/head_tracker.h"
#include "vision/plane_mapping.h"
#include "vision/plate_pose.h"
#include "vision/video_reader.h"

namespace softbench {

// A stretch of video time, [start_s, end_s).
struct TimeSpan {
  double start_s = 0.0;
  double end_s = 0.0;
};

struct VideoMeasurementOptions {
  // Frames from the start whose tag corners are combined (median).
  int tag_frames = 10;
  // The rest position is the median over the frames before the first
  // actuation (plan times) or, without times, over the first `rest_s`.
  double rest_s = 1.0;
  HeadTrackerOptions tracker;
  // Register every frame to the bench through the plan's tag, so a camera
  // that drifts, trembles or is bumped does not move the heads (plans with
  // a tag; without one the camera is taken to be still).
  bool register_frames = true;
  BenchRegistrationOptions registration;
  CameraPathOptions camera_path;
  // Each head's lift and tilt out of the dot plane is measured in every
  // frame from its dots against their rest (vision/plate_pose.h); with
  // correct_lift (track --lift-correction; validate decides after scoring,
  // pipelines/validation/lift_correction.h) the parallax they cause is
  // taken out of its position, so the displacement is the head's motion in
  // the plane (issue 27). Off by default: from three dots 11 mm apart the lift
  // is known to about 0.1 mm at 1080p and 10 Mb/s, and a head 50 mm off the
  // camera's axis would gain 0.01 mm of noise (docs/measurement.md, "Out of the
  // plane").
  bool correct_lift = false;
  // The pose's fit (FitPlatePose), its dots weighed at plate_dot_sigma_px.
  PlatePoseOptions plate_pose;
  // One dot's error that a window's frames share [px]: the codec's still
  // picture (0.01-0.02 px at 10 Mb/s) and a phone's sharpening, whose bias
  // follows the dot's pixel phase (docs/measurement.md). It weighs the
  // plate's tilt prior against its dots, at the footage's scale (times
  // VideoMeasurement::mm_per_px).
  double plate_dot_sigma_px = 0.02;
  // When the tag's border names an effect of the camera's processing.
  CameraProcessingOptions camera_processing;
  // Where that processing puts a small-celled tag's scale at risk, the tag
  // fitted whole on the first frame (vision/tag_model.h), its corners then
  // moved by the fit's offset from the midlines' wherever the mapping is
  // made (issue 28). The luma encoding is the video's.
  TagModelOptions tag_model;
  // Only the frames in these spans are measured, seeking from one to the
  // next (validate --windows-only); empty: every frame.
  std::vector<TimeSpan> spans;
  // Times whose frames' head crops are kept (for the report's pictures).
  std::vector<double> snapshot_times_s;
  // With the test times not yet known (found from the motion afterwards):
  // the crops that may turn out to be the windows' middles are kept on the
  // way (window_frames.h) instead of sought afterwards; empty: none kept.
  std::optional<WindowFrameKeeperOptions> window_frames;
  bool progress = true;

  std::optional<std::string> Problem() const;
};

// The distortion check without intrinsics: the dots' spacing, measured
// through the mapping, over the plan's layout spacing, at every frame.
struct DistortionCheck {
  bool performed = false;
  // The dots' mean spacing through the mapping over the layout's, per
  // frame and head: the median, and the 5th and 95th percentiles.
  double median_ratio = 1.0;
  double min_ratio = 1.0, max_ratio = 1.0;
  // How far the dots' shape departs from the layout's once scaled to it:
  // each pair's distance as a fraction of the pairs' mean, its median over
  // the frames against the layout's, RMS over the pairs; the worst head
  // (`shape_head`, -1: no head with three dots, whose shape can be
  // checked). It tells a layout that is not the printed dots (which then
  // cannot check the scale) from a scale that is off.
  double shape_misfit = 0.0;
  int shape_head = -1;
  // The dots' height above the tag that would explain median_ratio, were
  // the prints right [mm]; NaN without a tag's pose.
  double implied_plane_offset_mm = std::numeric_limits<double>::quiet_NaN();
  double tolerance = 0.0;
  bool warn = false;
  std::string message;
};

struct VideoMeasurement {
  std::string video_path;
  std::string scale_source;  // "tag 0 (10 frames)", "mm_per_px", ...
  double mm_per_px = 0.0;    // at the image centre, dot plane
  std::vector<Eigen::Vector2d> rest_mm;  // per head, plane coordinates
  // Per head, its dots' rest positions [mm] (medians over the rest frames
  // with the head complete): the reference of its lift and tilt
  // (HeadSample::lift_mm).
  std::vector<std::vector<Eigen::Vector2d>> rest_dots_mm;
  // The options and the dots' standard error [mm] the lift and tilt were
  // fitted with (MeasurePlatePoses), for the lift's uncertainty to be
  // propagated through the same fit.
  PlatePoseOptions plate_pose;
  double plate_dot_sigma_mm = 0.0;
  // The displacements have the lift's parallax taken out
  // (VideoMeasurementOptions::correct_lift, or TakeOutParallax).
  bool lift_corrected = false;
  std::vector<FrameSample> frames;  // in time order
  double fps = 0.0;                 // average
  // The median interval between frames (phones write variable frame rate).
  double frame_interval_s = 0.0;
  // The video's format and colours (VideoInfo::Description()).
  std::string video_format;
  // Time of the video's last frame (its end, as far as windows go).
  double last_frame_s = 0.0;
  bool every_frame = true;  // false: only the requested spans were read
  std::optional<PlaneMapping> mapping;
  // How `mapping` depends on the intrinsics' standard errors (the budget's
  // intrinsics term); not Known() without them.
  IntrinsicsSensitivity intrinsics_sensitivity;
  std::vector<FrameSnapshot> snapshots;  // in time order
  // Crops kept for the windows' middles before the times were known
  // (VideoMeasurementOptions::window_frames), in time order.
  std::vector<FrameSnapshot> window_frames;
  int missing_dots = 0;       // dot-frames without a dot
  int full_frame_frames = 0;  // frames that needed a full-image search
  int rejected_blobs = 0;     // same-colour blobs rejected in all frames
  // How frames were registered to the bench ("every frame, by tag 3", or
  // why not), and the frames that could not be, with the first reason.
  std::string registration;
  bool registers_frames = false;
  int unregistered_frames = 0;
  std::string unregistered_reason;
  // Frames lost to damaged video data: decoded with errors (also marked in
  // `frames`), or listed by the container but never decoded (only here).
  int damaged_frames = 0;
  std::vector<double> lost_frame_times_s;  // the never-decoded ones, sorted
  DistortionCheck distortion;
  // What the tag's border showed of the camera's processing (issue 28).
  CameraProcessing camera_processing;
};

// Measures every frame of a video of the plan's mechanism (thesis 4.1.3,
// done with sub-pixel centres and a calibrated scale). Throws InputError
// when the scale or the first frame's heads cannot be found, saying what was
// seen and what to change.
// `reader` is the video opened once for all of it (MeasurementReaderOptions,
// at its start): the tag's frames, the first frame's reference, every frame
// or the windows, and later CaptureSnapshots all go through it.
VideoMeasurement MeasureVideo(const TestPlan& plan, VideoReader* reader,
                              const VideoMeasurementOptions& options);
// The same, opening the video.
VideoMeasurement MeasureVideo(const TestPlan& plan,
                              const std::string& video_path,
                              const VideoMeasurementOptions& options);

// Takes each head's parallax (HeadSample::parallax_mm, where its pose was
// found) out of its displacement in every frame, as correct_lift does while
// measuring: for a caller that decides from the measured lifts whether the
// heads left the plane (validate's lift correction). Once only.
void TakeOutParallax(VideoMeasurement* m);

// How MeasureVideo wants its reader: luma only, frame threads when reading
// every frame, one thread when seeking from window to window.
VideoReaderOptions MeasurementReaderOptions(bool every_frame);

// The stretches of frames that could not be registered to the bench, for
// messages: "frames 61-330 (t = 2.033-11.000 s), frame 402 (...)" (at most
// five, then how many more).
std::string UnregisteredSpans(const std::vector<FrameSample>& frames);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_MEASUREMENT_VIDEO_MEASUREMENT_H_
