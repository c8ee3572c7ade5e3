#include "pipelines/measurement/window_frames.h"

#include <gtest/gtest.h>

#include <cmath>

#include "pipelines/measurement/test_point_detection.h"
#include "tests/support/held_measurement.h"

namespace softbench {
namespace {

// SettlingMeasurement's frames; every `partial_every`-th frame misses a dot
// (0: none does).
std::vector<FrameSample> Frames(const std::vector<HeadStep>& steps,
                                double end_s, double tau_s, double noise_mm,
                                int partial_every) {
  std::vector<FrameSample> frames =
      SettlingMeasurement(steps, end_s, tau_s, noise_mm).frames;
  for (size_t i = 0; partial_every > 0 && i < frames.size();
       i += partial_every) {
    frames[i].heads[0].observation.complete = false;
    frames[i].heads[0].displacement_mm.setConstant(NAN);
  }
  return frames;
}

// A 20x20 crop per candidate, as SnapshotHeads would cut.
FrameSnapshot Crop(const FrameSample& sample) {
  FrameSnapshot snapshot;
  snapshot.frame = sample.frame;
  snapshot.time_s = sample.time_s;
  snapshot.requested_s = sample.time_s;
  snapshot.heads.push_back(
      {cv::Mat(20, 20, CV_8UC3, cv::Scalar::all(1)), Eigen::Vector2d::Zero()});
  return snapshot;
}

std::vector<FrameSnapshot> Kept(const std::vector<FrameSample>& frames,
                                const WindowFrameKeeperOptions& options,
                                int* crops_cut = nullptr) {
  WindowFrameKeeper keeper(options);
  int cut = 0;
  for (const FrameSample& f : frames) {
    keeper.Offer(f, [&] {
      ++cut;
      return Crop(f);
    });
  }
  keeper.Finish();
  if (crops_cut != nullptr) *crops_cut = cut;
  return keeper.TakeKept();
}

double NearestOffsetS(const std::vector<FrameSnapshot>& kept, double t) {
  double nearest = INFINITY;
  for (const FrameSnapshot& s : kept) {
    nearest = std::min(nearest, std::abs(s.time_s - t));
  }
  return nearest;
}

const std::vector<HeadStep> kSteps = {{2.0, 7.0, {-1.1, 0.65}},
                                      {10.0, 15.0, {0.0, 1.29}},
                                      {18.0, 23.0, {-0.19, 0.11}},
                                      {26.0, 31.0, {0.0, -0.2}}};

// Whatever the settling time, noise or lost dots, every window's middle
// (half a window before each actuation and release the motion shows, and
// before the video's end) has a kept frame within a stride, at a few
// frames per window. (A step of a few motion_mm that settles slowly first
// moves beyond motion_mm well after its 10 % crossing: its middles are
// sought instead.)
TEST(WindowFrameKeeper, KeepsAFrameNearEveryWindowsMiddle) {
  for (double tau : {0.05, 0.15, 0.4}) {
    for (double noise : {0.0005, 0.004}) {
      for (int partial_every : {0, 7}) {
        const std::vector<FrameSample> frames =
            Frames(kSteps, 34.0, tau, noise, partial_every);
        const WindowFrameKeeperOptions options;
        const std::vector<FrameSnapshot> kept = Kept(frames, options);
        VideoMeasurement m;
        m.frames = frames;
        const TestPointDetection d = DetectTestPoints(
            m, static_cast<int>(kSteps.size()), TestPointDetectionOptions());
        ASSERT_TRUE(d.found) << d.why_not;
        std::vector<double> middles = {frames.back().time_s};
        for (const DetectedTestPoint& p : d.points) {
          middles.push_back(p.actuate_s);
          middles.push_back(p.release_s);
        }
        for (double& t : middles) t -= 0.5 * options.window_s;
        const std::string where = ::testing::PrintToString(
            std::make_tuple(tau, noise, partial_every));
        for (double t : middles) {
          EXPECT_LE(NearestOffsetS(kept, t), options.stride_s)
              << where << ": middle " << t;
        }
        EXPECT_LE(kept.size(), 6 * middles.size()) << where;
        for (size_t i = 1; i < kept.size(); ++i) {
          EXPECT_LT(kept[i - 1].time_s, kept[i].time_s) << where;
        }
      }
    }
  }
}

// A still video: only the last window's middle, before its end, is kept,
// and candidates are cut once a stride, not every frame.
TEST(WindowFrameKeeper, KeepsOnlyTheEndOfAStillVideo) {
  const std::vector<FrameSample> frames = Frames({}, 20.0, 0.15, 0.002, 0);
  int cut = 0;
  const std::vector<FrameSnapshot> kept =
      Kept(frames, WindowFrameKeeperOptions(), &cut);
  ASSERT_FALSE(kept.empty());
  EXPECT_LE(kept.size(), 4u);
  for (const FrameSnapshot& s : kept) {
    EXPECT_NEAR(s.time_s, frames.back().time_s - 0.5, 0.16);
  }
  EXPECT_NEAR(cut, static_cast<double>(frames.size()) / 3.0, 2.0);
}

// Past the memory bound nothing more is kept: the rest are sought.
TEST(WindowFrameKeeper, StaysWithinItsMemoryBound) {
  const std::vector<FrameSample> frames = Frames(kSteps, 34.0, 0.15, 0.001, 0);
  const double crop_mb = 20.0 * 20.0 * 3.0 / (1024.0 * 1024.0);
  WindowFrameKeeperOptions options;
  options.max_kept_mb = 5.5 * crop_mb;
  EXPECT_EQ(Kept(frames, options).size(), 5u);
  options.max_kept_mb = 0.0;
  EXPECT_TRUE(Kept(frames, options).empty());
}

TEST(WindowFrameKeeperOptions, NamesTheBadField) {
  WindowFrameKeeperOptions options;
  EXPECT_FALSE(options.Problem());
  options.stride_s = 0.3;  // more than a quarter of the 1 s window
  EXPECT_NE(options.Problem()->find("stride_s"), std::string::npos);
  options = {};
  options.motion_mm = 0.0;
  EXPECT_NE(options.Problem()->find("motion_mm"), std::string::npos);
}

}  // namespace
}  // namespace softbench
