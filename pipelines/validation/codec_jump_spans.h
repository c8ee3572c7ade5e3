#ifndef SOFTBENCH_PIPELINES_VALIDATION_CODEC_JUMP_SPANS_H_
#define SOFTBENCH_PIPELINES_VALIDATION_CODEC_JUMP_SPANS_H_

#include <optional>
#include <string>
#include <vector>

#include "pipelines/formats/test_plan.h"
#include "pipelines/measurement/video_measurement.h"
#include "vision/video_reader.h"

namespace softbench {

struct CodecJumpSpanOptions {
  // How long after a pressure change a head is taken to be still [s]: a
  // key frame nearer a change than this is not read for a jump. Only a
  // guess at where jumps are; StillIntraJumps checks the stillness itself.
  double settle_s = 1.0;
  // Frames read on each side of a key frame (StillIntraJumps uses up to 8).
  int frames_per_side = 8;

  std::optional<std::string> Problem() const;
};

// What --windows-only reads besides the windows so that the uncertainty's
// codec term is measured (docs/uncertainty.md, "Where I pictures fall").
struct CodecJumpSpans {
  // Stretches of `frames_per_side` frames either side of chosen key frames,
  // in time order; empty when the windows hold jumps enough.
  std::vector<TimeSpan> spans;
  // Still-head jumps expected inside the windows, and in the spans.
  int window_jumps = 0;
  int span_jumps = 0;
};

// The codec term is half the mean square jump of a still head at the
// I pictures; read through the windows alone it sees only the key frames
// inside them, and a plan whose period is a multiple of the key-frame
// interval puts none where a head is still on both sides (the delta
// sample). Then key frames of the rests and holds (after the first
// actuation, `settle_s` clear of every pressure change) are added, half
// from each where there are, spread evenly over the video: a displacement
// is one rest window against one hold window, and the codec's errors differ
// between the two (a hold's key frames alone gave a budget 0.85x the
// error). `window_spans` are the spans already to be read, `min_jumps` the
// jumps the codec term should rest on (ValidationOptions::min_codec_jumps).
// Needs the
// plan's times and the video's key frames (none: no spans).
CodecJumpSpans PlanCodecJumpSpans(const TestPlan& plan,
                                  const std::vector<TimeSpan>& window_spans,
                                  const VideoInfo& info, int min_jumps,
                                  const CodecJumpSpanOptions& options);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_VALIDATION_CODEC_JUMP_SPANS_H_
