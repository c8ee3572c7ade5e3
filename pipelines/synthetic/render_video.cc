#include "pipelines/synthetic/render_video.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <future>
#include <opencv2/core.hpp>
#include <vector>

#include "pipelines/synthetic/render_timeline.h"
#include "util/check.h"
#include "util/input_error.h"
#include "util/progress.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

// Sub-exposure samples for motion blur: none needed when the heads move less
// than 1e-6 mm during the exposure.
std::vector<Eigen::VectorXd> ExposureSamples(const HeadTimeline& timeline,
                                             double time_s, double exposure_s,
                                             bool motion_blur) {
  constexpr int kSamples = 4;
  if (!motion_blur || exposure_s <= 0.0) return {timeline.StateAt(time_s)};
  std::vector<Eigen::VectorXd> samples;
  for (int j = 0; j < kSamples; ++j) {
    samples.push_back(
        timeline.StateAt(time_s + exposure_s * ((j + 0.5) / kSamples - 0.5)));
  }
  if ((samples.front() - samples.back()).lpNorm<Eigen::Infinity>() < 1e-6) {
    return {timeline.StateAt(time_s)};
  }
  return samples;
}

// Each frame's time: k / fps, or with a variable frame rate moved by up to
// `jitter` / 2 frame intervals either way (seeded), on the phone's clock.
std::vector<double> FrameTimes(int64_t frames, double fps, double jitter,
                               uint64_t seed) {
  std::vector<double> times(frames);
  cv::RNG rng(seed * 0x2545F4914F6CDD1DULL + 7);
  for (int64_t k = 0; k < frames; ++k) {
    times[k] = k / fps;
    if (jitter > 0.0 && k > 0) {
      const double t = (k + jitter * rng.uniform(-0.5, 0.5)) / fps;
      times[k] = std::round(t * kPhoneClockHz) / kPhoneClockHz;
    }
  }
  return times;
}

std::string TruthHeader(int num_heads) {
  std::string header = "frame,time_s";
  for (int h = 1; h <= num_heads; ++h) {
    header += fmt::format(",y{0}_mm,z{0}_mm,u{0}_px,v{0}_px", h);
  }
  // Each head's lift toward the camera and its tilt about world y and z.
  for (int h = 1; h <= num_heads; ++h) {
    header += fmt::format(",lift{0}_mm,tilt_y{0}_rad,tilt_z{0}_rad", h);
  }
  // The camera's motion since the start: the shift of the content at the
  // principal point and the roll (clockwise on screen); the brightness.
  return header + ",camera_dx_px,camera_dy_px,camera_roll_rad,brightness\n";
}

// One frame's truth row: the heads where they were during the exposure
// (the mean of its samples) and the camera.
std::string TruthRow(int64_t k, double time_s, const SceneRenderer& renderer,
                     const std::vector<Eigen::VectorXd>& samples,
                     const FrameConditions& conditions,
                     const CameraIntrinsics& intrinsics) {
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(samples[0].size());
  for (const Eigen::VectorXd& s : samples) mean += s / samples.size();
  const int num_heads = static_cast<int>(mean.size() / 5);
  std::vector<Eigen::Vector2d> pixels(num_heads, Eigen::Vector2d::Zero());
  for (const Eigen::VectorXd& s : samples) {
    const std::vector<Eigen::Vector2d> p =
        renderer.HeadPixels(s, conditions.motion);
    for (size_t h = 0; h < p.size(); ++h) pixels[h] += p[h] / samples.size();
  }
  std::string row = fmt::format("{},{:.6f}", k, time_s);
  for (int h = 0; h < num_heads; ++h) {
    row += fmt::format(",{:.7f},{:.7f},{:.5f},{:.5f}", mean[2 * h],
                       mean[2 * h + 1], pixels[h].x(), pixels[h].y());
  }
  for (int h = 0; h < num_heads; ++h) {
    const auto pose = mean.segment<3>(2 * num_heads + 3 * h);
    row += fmt::format(",{:.7f},{:.8f},{:.8f}", pose[0], pose[1], pose[2]);
  }
  const Eigen::Vector2d shift = conditions.motion.ShiftPx(intrinsics);
  return row + fmt::format(",{:.5f},{:.5f},{:.8f},{:.5f}\n", shift.x(),
                           shift.y(), conditions.motion.roll_rad(),
                           conditions.brightness);
}

// Stored as the sensor saw it; players turn it upright by the rotation.
void TurnToStored(int rotation_deg, cv::Mat* frame) {
  if (rotation_deg == 0) return;
  cv::rotate(*frame, *frame,
             rotation_deg == 90    ? cv::ROTATE_90_COUNTERCLOCKWISE
             : rotation_deg == 180 ? cv::ROTATE_180
                                   : cv::ROTATE_90_CLOCKWISE);
}

// Renders and encodes every frame (one frame encodes while the next
// renders), returning the truth rows.
std::string RenderFrames(const TestPlan& plan, const RenderOptions& scene,
                         const RenderVideoOptions& options,
                         VideoWriter* writer) {
  const HeadTimeline timeline(plan);
  const SceneRenderer renderer(plan, scene);
  const double fps = options.writer.fps;
  const int64_t frames =
      static_cast<int64_t>(std::ceil(timeline.duration_s() * fps));
  const BenchConditions bench(options.conditions, scene.intrinsics,
                              timeline.duration_s());
  const std::vector<double> times =
      FrameTimes(frames, fps, options.vfr_jitter, scene.seed);
  std::string truth = TruthHeader(plan.mechanism.NumHeads());
  ProgressBar progress("render", frames, options.progress);
  std::future<void> encoding;
  TemporalDenoiser denoiser(options.temporal_denoise);
  for (int64_t k = 0; k < frames; ++k) {
    const double t = times[k];
    const FrameConditions conditions =
        bench.ReadOut(t, options.readout_s, options.writer.rotation_deg);
    const std::vector<Eigen::VectorXd> samples =
        ExposureSamples(timeline, t, scene.exposure_s, scene.motion_blur);
    truth += TruthRow(k, t, renderer, samples, conditions, scene.intrinsics);
    cv::Mat frame = renderer.Render(samples, k, conditions);
    denoiser.Apply(&frame);
    TurnToStored(options.writer.rotation_deg, &frame);
    if (encoding.valid()) encoding.get();
    const double stamp = options.vfr_jitter > 0.0 ? t : -1.0;
    encoding = std::async(
        std::launch::async,
        [writer, f = std::move(frame), stamp] { writer->Write(f, stamp); });
    progress.Update(k + 1);
  }
  if (encoding.valid()) encoding.get();
  progress.Finish();
  return truth;
}

}  // namespace

std::optional<std::string> RenderVideoOptions::Problem() const {
  if (auto problem = scene.Problem()) return "scene: " + *problem;
  if (auto problem = conditions.Problem()) return "conditions: " + *problem;
  if (auto problem = writer.Problem()) return "writer: " + *problem;
  if (auto problem = temporal_denoise.Problem()) {
    return "temporal_denoise: " + *problem;
  }
  if (!(vfr_jitter >= 0.0 && vfr_jitter <= 0.9)) {
    return "vfr_jitter: must be between 0 and 0.9";
  }
  if (vfr_jitter > 0.0 && writer.time_base_hz != kPhoneClockHz) {
    return fmt::format(
        "writer.time_base_hz: must be {} (the phone's clock) "
        "with a variable frame rate",
        kPhoneClockHz);
  }
  if (!(readout_s >= 0.0 && readout_s <= 1.0 / writer.fps)) {
    return "readout_s: must be between 0 and one frame interval";
  }
  if (scene.sixteen_bit != (writer.bit_depth > 8)) {
    return "scene.sixteen_bit: must be set exactly for a bit depth above 8";
  }
  return std::nullopt;
}

RenderedVideo RenderVideo(TestPlan plan, const std::string& video_path,
                          const RenderVideoOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  RenderOptions scene = options.scene;
  scene.exposure_s = std::min(scene.exposure_s, 1.0 / options.writer.fps);
  AssignTimes(&plan);
  const fs::path video(video_path);
  const fs::path temporary =
      video.parent_path() / ("." + video.stem().string() + ".partial" +
                             (video.extension() == ".mov" ? ".mov" : ".mp4"));
  const int rotation = options.writer.rotation_deg;
  const bool quarter_turn = rotation == 90 || rotation == 270;
  const int width = scene.intrinsics.width_px;
  const int height = scene.intrinsics.height_px;
  RenderedVideo rendered;
  try {
    VideoWriter writer(temporary.string(), quarter_turn ? height : width,
                       quarter_turn ? width : height, options.writer);
    rendered.truth_csv = RenderFrames(plan, scene, options, &writer);
    writer.Close();
  } catch (...) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw;
  }
  std::error_code error;
  fs::rename(temporary, video, error);
  if (error) {
    fs::remove(temporary, error);
    throw InputError(video.string() + ": cannot write the video (" +
                     error.message() + "); choose another --out");
  }
  rendered.frames = static_cast<int64_t>(
      std::count(rendered.truth_csv.begin(), rendered.truth_csv.end(), '\n') -
      1);
  rendered.duration_s = rendered.frames / options.writer.fps;
  rendered.plan = std::move(plan);
  return rendered;
}

}  // namespace softbench
