// Video benchmarks: render speed at 1080p and 4K, the choice of static
// patches on the samples' first frames, and, on the files named
// after "--" (made by bench/run_video_bench.sh, which also times ffmpeg and
// the Python/OpenCV peer on the same files), decode speed of VideoReader and
// measurement speed (region tracking, full-frame detection).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "pipelines/measurement/plan_camera.h"
#include "pipelines/measurement/video_measurement.h"
#include "pipelines/synthetic/scene_renderer.h"
#include "vision/color_segmentation.h"
#include "vision/frame_source.h"
#include "vision/head_tracker.h"
#include "vision/static_patches.h"
#include "vision/tag_detector.h"
#include "vision/tag_finder.h"
#include "vision/tag_model.h"
#include "vision/video_reader.h"

namespace softbench {
namespace {

TestPlan DeltaPlan() {
  return LoadTestPlan(std::string(SOFTBENCH_SOURCE_DIR) +
                      "/samples/delta/plan.yaml");
}

// The delta sample's scene (its tag and heads) as a 52 mm-equivalent lens
// sees it at `size`.
SceneRenderer DeltaScene(cv::Size size) {
  RenderOptions options;
  options.intrinsics =
      CameraIntrinsics::FromEquivalentFocalLength(52, size.width, size.height);
  return {DeltaPlan(), options};
}

// One frame of the delta sample's scene, heads still (one exposure sample) or
// moving (four, for motion blur).
void BM_RenderFrame(benchmark::State& state, cv::Size size, bool moving) {
  const SceneRenderer renderer = DeltaScene(size);
  int64_t frame = 0;
  for (auto _ : state) {
    std::vector<Eigen::VectorXd> samples;
    for (int j = 0; j < (moving ? 4 : 1); ++j) {
      const double phase = 0.01 * (4 * frame + j);
      samples.emplace_back(Eigen::Vector2d(std::sin(phase), std::cos(phase)));
    }
    benchmark::DoNotOptimize(renderer.Render(samples, frame++).data);
  }
  state.counters["fps"] = benchmark::Counter(
      static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK_CAPTURE(BM_RenderFrame, 1080p_still, cv::Size(1920, 1080), false)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_RenderFrame, 1080p_moving, cv::Size(1920, 1080), true)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_RenderFrame, 4k_still, cv::Size(3840, 2160), false)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Chooses the static patches in a sample's first frame, as registration does
// once per video before its first frame (serially, with the decoder
// waiting).
void BM_ChooseStaticPatches(benchmark::State& state, const std::string& name) {
  VideoReaderOptions options;
  options.want_bgr = false;
  VideoReader reader(std::string(SOFTBENCH_SOURCE_DIR) + "/samples/" + name +
                         "/" + name + ".mp4",
                     options);
  VideoFrame frame;
  reader.Read(&frame);
  const cv::Mat luma = frame.luma.clone();
  StaticPatchOptions patch_options;
  patch_options.luma_encoding = reader.info().luma_encoding();
  int patches = 0;
  for (auto _ : state) {
    patches = StaticPatches(luma, cv::Mat(), patch_options).size();
  }
  state.counters["patches"] = patches;
}
BENCHMARK_CAPTURE(BM_ChooseStaticPatches, delta, std::string("delta"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ChooseStaticPatches, phone, std::string("phone"))
    ->Unit(benchmark::kMillisecond);

// Finds the plan's tag in the first frame of a rendered delta scene, as
// `validate` does once per video with the decoder waiting: TagFinder (a
// coarse search at 640 px across, then the tag's region read) against the
// previous whole-frame search at libapriltag's half resolution.
void BM_FindTagInFirstFrame(benchmark::State& state, cv::Size size,
                            bool coarse) {
  cv::Mat luma;
  cv::cvtColor(DeltaScene(size).Render({Eigen::Vector2d::Zero()}, 0), luma,
               cv::COLOR_BGR2GRAY);
  const int id = DeltaPlan().calibration.tag->id;
  bool found = false;
  for (auto _ : state) {
    if (coarse) {
      TagFinder finder(id, {});
      found = finder.Find(luma).has_value();
    } else {
      found = false;
      for (const TagDetection& d : TagDetector().Detect(luma)) {
        found = found || d.id == id;
      }
    }
  }
  state.counters["found"] = found;
}
BENCHMARK_CAPTURE(BM_FindTagInFirstFrame, 1080p_coarse, cv::Size(1920, 1080),
                  true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FindTagInFirstFrame, 1080p_whole, cv::Size(1920, 1080),
                  false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FindTagInFirstFrame, 4k_coarse, cv::Size(3840, 2160), true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FindTagInFirstFrame, 4k_whole, cv::Size(3840, 2160), false)
    ->Unit(benchmark::kMillisecond);

// Fits the tag whole (vision/tag_model.h) in the delta scene at 720p (its
// cells 11 px) through a phone's S-curve 0.6 and sharpening 1.5 px x 1.0, as
// `validate` does once per video where the processing puts the midlines'
// scale at risk, with the decoder waiting.
void BM_FitTagModel(benchmark::State& state) {
  RenderOptions options;
  options.intrinsics =
      CameraIntrinsics::FromEquivalentFocalLength(52, 1280, 720);
  options.tone_curve = 0.6;
  options.sharpen_radius_px = 1.5;
  options.sharpen_amount = 1.0;
  cv::Mat luma;
  cv::cvtColor(
      SceneRenderer(DeltaPlan(), options).Render({Eigen::Vector2d::Zero()}, 0),
      luma, cv::COLOR_BGR2GRAY);
  const int id = DeltaPlan().calibration.tag->id;
  const std::optional<TagDetection> tag = TagFinder(id, {}).Find(luma);
  if (!tag) {
    state.SkipWithError("no tag in the rendered frame");
    return;
  }
  TagModelFit fit;
  for (auto _ : state) {
    fit =
        FitTagModel(luma, Tag36h11Bitmap(id), tag->corners, TagModelOptions());
  }
  state.counters["found"] = fit.found;
  state.counters["iterations"] = fit.iterations;
  state.counters["pixels"] = fit.pixels;
}
BENCHMARK(BM_FitTagModel)->Unit(benchmark::kMillisecond);

// A tracked dot's colour region as HeadTracker cuts it (1.5 dot radii
// each side of the dot's last centre): a red dot of `radius` px on the
// head's grey, with the codec's noise.
cv::Mat TrackedDotRegion(int radius) {
  const int half = static_cast<int>(std::ceil(1.5 * radius));
  cv::Mat bgr(2 * half + 1, 2 * half + 1, CV_8UC3, cv::Scalar(150, 160, 165));
  cv::circle(bgr, {half, half}, radius, cv::Scalar(45, 40, 190), cv::FILLED,
             cv::LINE_AA);
  cv::Mat noise(bgr.size(), CV_8UC3);
  cv::randn(noise, cv::Scalar::all(0), cv::Scalar::all(6));
  return bgr + noise;
}

// The colour mask of a tracked dot's region (red: a hue range that wraps)
// and its cleaning, as every frame does for every dot; `opencv` the same
// with OpenCV's cv::inRange (twice, for the wrap) and cv::morphologyEx
// (the peer: what CleanMask and ColorMask ran until 2026-12-06). The dot's
// radius is the delta sample's at 1080p (11 px) and at 4K (22 px).
void BM_TrackedDotMask(benchmark::State& state, bool opencv) {
  const int radius = static_cast<int>(state.range(0));
  const cv::Mat bgr = TrackedDotRegion(radius);
  const HsvRange red = HsvRange::FromBounds({170, 10, 100, 255, 50, 255});
  SegmentationOptions options;
  options.dot_radius_px = radius;
  const int r = std::max(
      1, static_cast<int>(std::lround(options.morphology_fraction * radius)));
  const cv::Mat disk =
      cv::getStructuringElement(cv::MORPH_ELLIPSE, {2 * r + 1, 2 * r + 1});
  int set = 0;
  for (auto _ : state) {
    cv::Mat mask;
    if (opencv) {
      cv::Mat hsv, upper;
      cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
      cv::inRange(hsv,
                  cv::Scalar(red.hue_low, red.saturation_low, red.value_low),
                  cv::Scalar(179, red.saturation_high, red.value_high), upper);
      cv::inRange(hsv, cv::Scalar(0, red.saturation_low, red.value_low),
                  cv::Scalar(red.hue_high, red.saturation_high, red.value_high),
                  mask);
      mask |= upper;
      cv::morphologyEx(mask, mask, cv::MORPH_OPEN, disk);
      cv::morphologyEx(mask, mask, cv::MORPH_CLOSE, disk);
    } else {
      mask = ColorMask(bgr, red);
      CleanMask(options, &mask);
    }
    set = cv::countNonZero(mask);
  }
  state.counters["set_px"] = set;
}
BENCHMARK_CAPTURE(BM_TrackedDotMask, softbench, false)->Arg(11)->Arg(22);
BENCHMARK_CAPTURE(BM_TrackedDotMask, opencv, true)->Arg(11)->Arg(22);

// Decodes the whole file: decode only (Skip), or with the luma plane each
// later stage reads.
void BM_Decode(benchmark::State& state, const std::string& path, bool luma) {
  int64_t frames = 0;
  for (auto _ : state) {
    VideoReaderOptions options;
    options.want_bgr = false;
    options.want_luma = luma;
    VideoReader reader(path, options);
    VideoFrame frame;
    frames = 0;
    while (luma ? reader.Read(&frame) : reader.Skip()) ++frames;
  }
  state.counters["frames"] = static_cast<double>(frames);
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(frames),
                         benchmark::Counter::kIsIterationInvariantRate);
}

// Measures every head in every frame of a rendered clip (its plan is the
// plan.yaml beside it): region tracking after the first frame, or the full
// image every frame. The scale comes from the tag once, outside the timing.
void BM_Measure(benchmark::State& state, const std::string& path,
                bool full_frame) {
  const std::string plan_path =
      path.substr(0, path.find_last_of('/') + 1) + "plan.yaml";
  const TestPlan plan = LoadTestPlan(plan_path);
  VideoReaderOptions options;
  options.want_bgr = false;
  VideoReader probe(path, options);
  const CameraIntrinsics intrinsics =
      PlanIntrinsics(plan, probe.info().width_px, probe.info().height_px);
  std::string source;
  const PlaneMapping mapping =
      PlanMapping(plan, &probe, intrinsics, 3, &source);
  HeadTrackerOptions tracker_options;
  tracker_options.full_frame_every_frame = full_frame;
  int64_t frames = 0, missing = 0;
  for (auto _ : state) {
    VideoReader reader(path, options);
    HeadTracker tracker(mapping, PlanHeadMarkers(plan), tracker_options);
    VideoFrame frame;
    frames = missing = 0;
    while (reader.Read(&frame)) {
      for (const HeadObservation& o :
           tracker.Measure(VideoFrameSource(&reader, &frame))) {
        missing += static_cast<int64_t>(o.dots.size()) - o.dots_found;
      }
      ++frames;
    }
  }
  state.counters["frames"] = static_cast<double>(frames);
  state.counters["missing_dots"] = static_cast<double>(missing);
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(frames),
                         benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace
}  // namespace softbench

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  // Files after "--" get decode benchmarks.
  bool files = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--") {
      files = true;
      continue;
    }
    if (!files) continue;
    const std::string name = arg.substr(arg.find_last_of('/') + 1);
    benchmark::RegisterBenchmark(("BM_Decode/" + name + "/decode_only").c_str(),
                                 softbench::BM_Decode, arg, false)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
    benchmark::RegisterBenchmark(("BM_Decode/" + name + "/with_luma").c_str(),
                                 softbench::BM_Decode, arg, true)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
    benchmark::RegisterBenchmark(("BM_Measure/" + name + "/tracking").c_str(),
                                 softbench::BM_Measure, arg, false)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
    benchmark::RegisterBenchmark(("BM_Measure/" + name + "/full_frame").c_str(),
                                 softbench::BM_Measure, arg, true)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
