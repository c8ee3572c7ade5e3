#ifndef SOFTBENCH_PIPELINES_MEASUREMENT_SNAPSHOTS_H_
#define SOFTBENCH_PIPELINES_MEASUREMENT_SNAPSHOTS_H_

#include <vector>

#include "pipelines/formats/test_plan.h"
#include "pipelines/measurement/video_measurement.h"
#include "vision/frame_source.h"
#include "vision/video_reader.h"

namespace softbench {

// The measured frame nearest `time_s`, or null when none is within one frame
// interval (frames are found by time: under variable frame rate frame k is
// not at k / fps).
const FrameSample* FindFrame(const VideoMeasurement& measurement,
                             double time_s);

// Cuts each head of a measured frame out of it: the box of its dots, grown
// by 2.5 dot diameters on every side (room for the predictions around it).
FrameSnapshot SnapshotHeads(const FrameSource& frame, const FrameSample& sample,
                            const TestPlan& plan, double mm_per_px,
                            double requested_s);

// Adds the snapshots at `times_s` to a finished measurement (used when the
// times were known only after measuring: test points found from the motion
// or a pressure log): each from the crops kept on the way
// (measurement->window_frames, then dropped) when one is within
// `max_offset_s` of it, else by seeking `reader` (the measurement's own) to
// its frame.
void CaptureSnapshots(const TestPlan& plan, const std::vector<double>& times_s,
                      double max_offset_s, VideoReader* reader,
                      VideoMeasurement* measurement);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_MEASUREMENT_SNAPSHOTS_H_
