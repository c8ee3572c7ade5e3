// What --windows-only reads besides the windows so that the uncertainty's
// codec term is measured (pipelines/validation/codec_jump_spans.h): on a
// plan whose period is a multiple of the key-frame interval (the delta
// sample's kind), and on one whose windows hold key frames enough.
#include "pipelines/validation/codec_jump_spans.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "pipelines/validation/uncertainty_budget.h"
#include "pipelines/validation/validation.h"
#include "tests/support/coverage.h"
#include "tests/support/held_measurement.h"

namespace softbench {
namespace {

// A 30 fps video of `end_s` with a key frame every `key_interval_s`.
VideoInfo VideoWithKeyFrames(double end_s, double key_interval_s) {
  VideoInfo info;
  info.fps = 30.0;
  info.frame_interval_s = 1.0 / 30.0;
  for (int k = 0; k / 30.0 <= end_s; ++k)
    info.frame_times_s.push_back(k / 30.0);
  info.frame_count = static_cast<int64_t>(info.frame_times_s.size());
  info.duration_s = info.frame_times_s.back() + info.frame_interval_s;
  for (double t = 0.0; t <= end_s; t += key_interval_s) {
    info.key_frame_times_s.push_back(info.frame_times_s[info.NearestFrame(t)]);
  }
  return info;
}

// The windows' spans, as validate --windows-only reads them.
std::vector<TimeSpan> WindowSpans(const TestPlan& plan, double end_s) {
  std::vector<TimeSpan> spans;
  for (const auto& test : PlanWindows(plan, end_s)) {
    for (const WindowSummary& w : test) spans.push_back({w.start_s, w.end_s});
  }
  return spans;
}

// The frames of `m` inside any of `spans`, as a windows-only run has them.
VideoMeasurement FramesIn(const VideoMeasurement& m,
                          const std::vector<TimeSpan>& spans) {
  VideoMeasurement read = m;
  read.every_frame = false;
  read.frames.clear();
  for (const FrameSample& f : m.frames) {
    if (std::any_of(spans.begin(), spans.end(), [&](const TimeSpan& s) {
          return f.time_s >= s.start_s && f.time_s <= s.end_s;
        })) {
      read.frames.push_back(f);
    }
  }
  return read;
}

TEST(PlanCodecJumpSpans, ReadsKeyFramesOfRestsAndHoldsClearOfEveryChange) {
  const TestPlan plan = TimedDeltaPlan(14);
  const double end_s = 86.0;
  const VideoInfo info = VideoWithKeyFrames(end_s, 1.0);
  const std::vector<TimeSpan> windows = WindowSpans(plan, end_s);
  const CodecJumpSpanOptions options;
  const CodecJumpSpans planned =
      PlanCodecJumpSpans(plan, windows, info, 10, options);
  // Every window ends at a change on a key frame: none inside a window.
  EXPECT_EQ(planned.window_jumps, 0);
  ASSERT_EQ(planned.spans.size(), 10u);
  EXPECT_EQ(planned.span_jumps, 10);
  int held = 0;
  for (const TimeSpan& span : planned.spans) {
    const double key_s = 0.5 * (span.start_s + span.end_s);
    EXPECT_NEAR(span.end_s - span.start_s, 17.0 / 30.0, 1e-9);
    EXPECT_GE(span.start_s, *plan.tests.front().actuate_s);
    for (const TestPoint& test : plan.tests) {
      for (const double change : {*test.actuate_s, *test.release_s}) {
        EXPECT_FALSE(span.start_s < change + options.settle_s &&
                     span.end_s > change)
            << "span around " << key_s << " s meets the change at " << change;
      }
      held += key_s > *test.actuate_s && key_s < *test.release_s;
    }
    // Not a key frame whose jump a window shows already (it may start one).
    for (const TimeSpan& w : windows) {
      EXPECT_FALSE(key_s - 0.1 > w.start_s && key_s + 0.1 < w.end_s);
    }
  }
  // Half of them in holds, half in rests, spread over the video.
  EXPECT_EQ(held, 5);
  EXPECT_LT(planned.spans.front().start_s, 0.25 * end_s);
  EXPECT_GT(planned.spans.back().end_s, 0.75 * end_s);
}

TEST(PlanCodecJumpSpans, AddsNothingWhenTheWindowsHoldJumpsEnough) {
  const TestPlan plan = TimedDeltaPlan(14);
  const double end_s = 86.0;
  // Key frames every 0.3 s: each 1 s window holds two or more well inside.
  const CodecJumpSpans planned = PlanCodecJumpSpans(
      plan, WindowSpans(plan, end_s), VideoWithKeyFrames(end_s, 0.3), 10,
      CodecJumpSpanOptions());
  EXPECT_GE(planned.window_jumps, 10);
  EXPECT_TRUE(planned.spans.empty());
  EXPECT_EQ(planned.span_jumps, 0);
}

// Every frame a key frame (an intra-only video): no jump anywhere, so
// nothing is worth reading for one.
TEST(PlanCodecJumpSpans, ReadsNothingForAnIntraOnlyVideo) {
  const TestPlan plan = TimedDeltaPlan(14);
  const double end_s = 86.0;
  const CodecJumpSpans planned = PlanCodecJumpSpans(
      plan, WindowSpans(plan, end_s), VideoWithKeyFrames(end_s, 1.0 / 30.0), 10,
      CodecJumpSpanOptions());
  EXPECT_EQ(planned.window_jumps, 0);
  EXPECT_TRUE(planned.spans.empty());
}

// End to end on a codec's kind of error (a level per head drawn afresh at
// each I picture, 1 s apart, and repeated until the next): the windows alone
// show no jump, the planned spans show as many as the codec term needs.
TEST(PlanCodecJumpSpans, GiveTheCodecTermTheJumpsItNeeds) {
  const TestPlan plan = TimedDeltaPlan(14);
  const double end_s = 86.0;
  VideoMeasurement m = HeldMeasurement(plan, end_s, 0.0);
  for (FrameSample& f : m.frames) {
    f.intra = f.frame % 30 == 0;
    f.heads[0].displacement_mm.x() += 0.002 * std::sin(f.frame / 30);
  }
  const std::vector<TimeSpan> windows = WindowSpans(plan, end_s);
  ASSERT_EQ(MeasureCodecLevel(FramesIn(m, windows)).jumps, 0);
  const CodecJumpSpans planned =
      PlanCodecJumpSpans(plan, windows, VideoWithKeyFrames(end_s, 1.0), 10,
                         CodecJumpSpanOptions());
  std::vector<TimeSpan> read = windows;
  read.insert(read.end(), planned.spans.begin(), planned.spans.end());
  const CodecLevel codec = MeasureCodecLevel(FramesIn(m, read));
  EXPECT_EQ(codec.jumps, 10);
  EXPECT_GT(codec.variance_mm2.x(), 1e-7);
}

TEST(CodecJumpSpanOptions, ProblemNamesTheBadField) {
  EXPECT_FALSE(CodecJumpSpanOptions().Problem());
  CodecJumpSpanOptions options;
  options.frames_per_side = 2;
  EXPECT_NE(options.Problem()->find("frames_per_side"), std::string::npos);
  options = CodecJumpSpanOptions();
  options.settle_s = NAN;
  EXPECT_NE(options.Problem()->find("settle_s"), std::string::npos);
}

}  // namespace
}  // namespace softbench
