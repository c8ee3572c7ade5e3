#include "pipelines/render_command.h"

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <future>
#include <opencv2/core.hpp>

#include "pipelines/model_selection.h"
#include "pipelines/render_timeline.h"
#include "util/atomic_file.h"
#include "util/input_error.h"
#include "util/progress.h"
#include "vision/video_reader.h"
#include "vision/video_writer.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

// Sub-exposure samples for motion blur: none needed when the heads move less
// than 1e-6 mm during the exposure.
std::vector<Eigen::VectorXd> ExposureSamples(const HeadTimeline& timeline,
                                             double time_s, double exposure_s,
                                             bool motion_blur) {
  constexpr int kSamples = 4;
  if (!motion_blur || exposure_s <= 0.0)
    return {timeline.DisplacementAt(time_s)};
  std::vector<Eigen::VectorXd> samples;
  for (int j = 0; j < kSamples; ++j) {
    samples.push_back(timeline.DisplacementAt(
        time_s + exposure_s * ((j + 0.5) / kSamples - 0.5)));
  }
  if ((samples.front() - samples.back()).lpNorm<Eigen::Infinity>() < 1e-6) {
    return {timeline.DisplacementAt(time_s)};
  }
  return samples;
}

// iPhones' timestamp clock [ticks per second].
constexpr int kPhoneClockHz = 600;

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

}  // namespace

cv::Size ParseResolution(const std::string& text) {
  if (text == "720p") return {1280, 720};
  if (text == "1080p") return {1920, 1080};
  if (text == "4k") return {3840, 2160};
  int w = 0, h = 0;
  char x = 0;
  if (std::sscanf(text.c_str(), "%d%c%d", &w, &x, &h) == 3 && x == 'x' &&
      w >= 16 && h >= 16 && w <= 8192 && h <= 8192 && w % 2 == 0 &&
      h % 2 == 0) {
    return {w, h};
  }
  throw InputError("--resolution: '" + text +
                   "' is not 720p, 1080p, 4k or WxH with even sides");
}

void AddRenderCommand(CLI::App* app, RenderCommandOptions* options) {
  CLI::App* c = app->add_subcommand(
      "render", "Render bench footage of a test plan, with exact ground truth");
  c->add_option("--plan", options->plan_path, "test plan YAML")->required();
  c->add_option("--output", options->output_path,
                "video to write (.mp4, or .mov for QuickTime)")
      ->required();
  c->add_option("--truth", options->truth_path, "per-frame truth CSV to write")
      ->required();
  c->add_option("--plan-out", options->plan_out_path,
                "the plan with the times used (default: VIDEO.plan.yaml)");
  c->add_option("--resolution", options->resolution, "720p, 1080p, 4k or WxH")
      ->capture_default_str();
  c->add_option("--codec", options->codec, "h264 or hevc")
      ->capture_default_str();
  c->add_option("--crf", options->crf,
                "encoder quality (lower: better, larger)")
      ->capture_default_str();
  c->add_option("--bitrate-mbps", options->bitrate_mbps,
                "average bitrate [Mb/s] instead of the CRF (a phone: ~10)");
  c->add_option("--preset", options->preset, "encoder preset")
      ->capture_default_str();
  c->add_option("--keyframe-interval-s", options->keyframe_interval_s,
                "seconds between key frames")
      ->capture_default_str();
  c->add_option("--fps", options->fps, "frames per second")
      ->capture_default_str();
  c->add_option("--seed", options->render.seed, "noise and texture seed")
      ->capture_default_str();
  c->add_option("--distance-mm", options->render.distance_mm,
                "camera to head tops, along the optical axis")
      ->capture_default_str();
  c->add_option("--focal-35mm", options->focal_35mm,
                "35 mm-equivalent focal length")
      ->capture_default_str();
  c->add_option("--focal-px", options->focal_px,
                "focal length in pixels (overrides --focal-35mm)");
  c->add_option("--principal-point", options->principal_point,
                "principal point cx,cy in pixels (default: the image centre)");
  c->add_option("--tilt-deg", options->tilt_deg,
                "camera tilt about the image x and y axes, e.g. 5,0");
  c->add_option("--distortion", options->distortion,
                "OpenCV distortion k1,k2,p1,p2,k3 (e.g. -0.1,0,0,0,0)");
  c->add_option("--noise-sigma", options->render.noise_sigma_dn,
                "Gaussian read noise, 8-bit levels")
      ->capture_default_str();
  c->add_option("--shot-noise", options->render.shot_noise_dn,
                "signal-dependent noise variance per level")
      ->capture_default_str();
  c->add_option("--supersampling", options->render.supersampling,
                "subsamples per pixel side on edges")
      ->capture_default_str();
  c->add_flag("--no-motion-blur", options->no_motion_blur,
              "sharp frames while moving");
  c->add_flag("--tube", options->render.red_tube,
              "add a red air tube distractor");
  c->add_flag("--glint", options->render.glint,
              "add a specular glint on each head");
  // A phone on a tripod (docs/rendering.md, "Real footage").
  c->add_option("--camera-drift-px", options->camera_drift_px,
                "camera drift dx,dy [px] reached linearly by the video's end, "
                "e.g. 0.4,0.3");
  c->add_option("--camera-tremor-px", options->conditions.tremor_px,
                "RMS camera tremble [px] (2-12 Hz)")
      ->capture_default_str();
  c->add_option("--camera-bump", options->camera_bumps,
                "a knock on the tripod: T:DX,DY[,ROLL_DEG] (s, px, deg); "
                "repeat for more");
  c->add_option("--exposure-drift", options->conditions.exposure_drift,
                "relative amplitude of auto-exposure's wander (0.3: +-30 %)")
      ->capture_default_str();
  c->add_option("--white-balance-drift-k",
                options->conditions.white_balance_drift_k,
                "amplitude of white balance's wander [K]")
      ->capture_default_str();
  c->add_option("--tag-gone-after-s", options->conditions.tag_gone_after_s,
                "take the tag away from this time on (a hand or a cable "
                "over it)");
  c->add_flag("--no-ring", options->no_ring,
              "a plain table around the mechanism: no ring or pads");
  c->add_option("--drift-period-s", options->conditions.drift_period_s,
                "period of the exposure wander [s] (white balance: 1.37x)")
      ->capture_default_str();
  c->add_option("--bit-depth", options->bit_depth,
                "bits per sample: 8, 10 or 12 (12 with hevc)")
      ->capture_default_str();
  c->add_option("--chroma", options->chroma,
                "chroma subsampling: 4:2:0 (phones), 4:2:2 or 4:4:4")
      ->capture_default_str();
  c->add_flag("--full-range", options->full_range,
              "full-range YUV (0-255) instead of limited (16-235)");
  c->add_option("--hdr", options->hdr,
                "HDR as a phone records it: hlg (iPhone's default) or pq, "
                "with BT.2020 colours, SDR white at BT.2408's reference "
                "white; needs --bit-depth 10 or 12");
  c->add_option("--rotation", options->rotation_deg,
                "display rotation to store, clockwise degrees (90: a phone "
                "held upright); --resolution is the upright picture")
      ->capture_default_str();
  c->add_option("--vfr-jitter", options->vfr_jitter,
                "variable frame rate: each frame's time moves by up to this "
                "fraction of the frame interval (0-0.9), on a 600 Hz clock "
                "as iPhones write")
      ->capture_default_str();
}

int RunRender(RenderCommandOptions options, std::ostream& out) {
  TestPlan plan = LoadTestPlan(options.plan_path);
  const cv::Size size = ParseResolution(options.resolution);
  if (!(options.focal_35mm > 0.0))
    throw InputError("--focal-35mm: must be > 0");
  RenderOptions& render = options.render;
  render.intrinsics = CameraIntrinsics::FromEquivalentFocalLength(
      options.focal_35mm, size.width, size.height);
  if (options.focal_px < 0.0) throw InputError("--focal-px: must be > 0");
  if (options.focal_px > 0.0) {
    render.intrinsics.fx_px = render.intrinsics.fy_px = options.focal_px;
  }
  if (!options.principal_point.empty()) {
    const std::vector<double> c =
        ParseNumberList(options.principal_point, "--principal-point");
    if (c.size() != 2) throw InputError("--principal-point: give cx,cy");
    render.intrinsics.cx_px = c[0];
    render.intrinsics.cy_px = c[1];
  }
  if (!options.tilt_deg.empty()) {
    const std::vector<double> tilt =
        ParseNumberList(options.tilt_deg, "--tilt-deg");
    if (tilt.size() != 2) throw InputError("--tilt-deg: give two angles, x,y");
    render.tilt_x_deg = tilt[0];
    render.tilt_y_deg = tilt[1];
  }
  if (!options.distortion.empty()) {
    const std::vector<double> d =
        ParseNumberList(options.distortion, "--distortion");
    if (d.size() != 5) throw InputError("--distortion: give k1,k2,p1,p2,k3");
    std::copy(d.begin(), d.end(), render.intrinsics.distortion.begin());
  }
  render.motion_blur = !options.no_motion_blur;
  render.ring = !options.no_ring;
  BenchConditionsOptions& conditions = options.conditions;
  if (!options.camera_drift_px.empty()) {
    const std::vector<double> d =
        ParseNumberList(options.camera_drift_px, "--camera-drift-px");
    if (d.size() != 2) throw InputError("--camera-drift-px: give dx,dy");
    conditions.drift_px = {d[0], d[1]};
  }
  for (const std::string& bump : options.camera_bumps) {
    conditions.bumps.push_back(ParseCameraBump(bump));
  }
  conditions.seed = render.seed;
  if (auto problem = conditions.Check())
    throw InputError("render: " + *problem);
  if (auto problem = render.Check()) throw InputError("render: " + *problem);
  VideoWriterOptions writer_options;
  writer_options.codec = options.codec;
  writer_options.crf = options.crf;
  writer_options.bitrate_mbps = options.bitrate_mbps;
  writer_options.preset = options.preset;
  writer_options.fps = options.fps;
  writer_options.keyframe_interval_s = options.keyframe_interval_s;
  writer_options.bit_depth = options.bit_depth;
  writer_options.chroma = options.chroma;
  writer_options.full_range = options.full_range;
  writer_options.rotation_deg = options.rotation_deg;
  if (!options.hdr.empty()) {
    if (options.hdr != "hlg" && options.hdr != "pq") {
      throw InputError("--hdr: '" + options.hdr + "' is not hlg or pq");
    }
    if (options.bit_depth < 10) {
      throw InputError("--hdr: HDR needs --bit-depth 10 or 12");
    }
    writer_options.encoding = {
        options.hdr == "hlg" ? Transfer::kHlg : Transfer::kPq,
        Primaries::kBt2020};
  }
  if (options.rotation_deg != 0 && options.rotation_deg != 90 &&
      options.rotation_deg != 180 && options.rotation_deg != 270) {
    throw InputError("--rotation: must be 0, 90, 180 or 270");
  }
  if (!(options.vfr_jitter >= 0.0 && options.vfr_jitter <= 0.9)) {
    throw InputError("--vfr-jitter: must be between 0 and 0.9");
  }
  if (options.vfr_jitter > 0.0) writer_options.time_base_hz = kPhoneClockHz;
  if (auto problem = writer_options.Check())
    throw InputError("render: " + *problem);
  render.sixteen_bit = options.bit_depth > 8;
  render.exposure_s = std::min(render.exposure_s, 1.0 / options.fps);

  AssignTimes(&plan);
  const HeadTimeline timeline(plan);
  const SceneRenderer renderer(plan, render);
  const int64_t frames =
      static_cast<int64_t>(std::ceil(timeline.duration_s() * options.fps));
  const BenchConditions bench(conditions, render.intrinsics,
                              timeline.duration_s());

  // The video goes to a temporary file renamed at the end: a failure leaves
  // no half-written video.
  const fs::path video(options.output_path);
  const fs::path temporary =
      video.parent_path() / ("." + video.stem().string() + ".partial" +
                             (video.extension() == ".mov" ? ".mov" : ".mp4"));
  const bool quarter_turn =
      options.rotation_deg == 90 || options.rotation_deg == 270;
  const cv::Size stored =
      quarter_turn ? cv::Size(size.height, size.width) : size;
  const std::vector<double> times =
      FrameTimes(frames, options.fps, options.vfr_jitter, render.seed);
  std::string truth = "frame,time_s";
  for (int h = 1; h <= plan.mechanism.NumHeads(); ++h) {
    truth += fmt::format(",y{0}_mm,z{0}_mm,u{0}_px,v{0}_px", h);
  }
  // The camera's motion since the start: the shift of the content at the
  // principal point and the roll (clockwise on screen); the brightness.
  truth += ",camera_dx_px,camera_dy_px,camera_roll_rad,brightness\n";
  try {
    VideoWriter writer(temporary.string(), stored.width, stored.height,
                       writer_options);
    ProgressBar progress("render", frames, !options.quiet);
    std::future<void> encoding;
    for (int64_t k = 0; k < frames; ++k) {
      const double t = times[k];
      const FrameConditions frame_conditions = bench.At(t);
      const std::vector<Eigen::VectorXd> samples =
          ExposureSamples(timeline, t, render.exposure_s, render.motion_blur);
      Eigen::VectorXd mean = Eigen::VectorXd::Zero(samples[0].size());
      for (const Eigen::VectorXd& s : samples) mean += s / samples.size();
      // The frame shows the heads where they were during the exposure.
      std::vector<Eigen::Vector2d> pixels(plan.mechanism.NumHeads(),
                                          Eigen::Vector2d::Zero());
      for (const Eigen::VectorXd& s : samples) {
        const std::vector<Eigen::Vector2d> p =
            renderer.HeadPixels(s, frame_conditions.motion);
        for (size_t h = 0; h < p.size(); ++h)
          pixels[h] += p[h] / samples.size();
      }
      truth += fmt::format("{},{:.6f}", k, t);
      for (int h = 0; h < plan.mechanism.NumHeads(); ++h) {
        truth += fmt::format(",{:.7f},{:.7f},{:.5f},{:.5f}", mean[2 * h],
                             mean[2 * h + 1], pixels[h].x(), pixels[h].y());
      }
      const Eigen::Vector2d shift =
          frame_conditions.motion.ShiftPx(render.intrinsics);
      truth += fmt::format(",{:.5f},{:.5f},{:.8f},{:.5f}\n", shift.x(),
                           shift.y(), frame_conditions.motion.roll_rad(),
                           frame_conditions.brightness);
      cv::Mat frame = renderer.Render(samples, k, frame_conditions);
      if (options.rotation_deg != 0) {
        // Stored as the sensor saw it; players turn it upright by the
        // rotation.
        cv::rotate(frame, frame,
                   options.rotation_deg == 90 ? cv::ROTATE_90_COUNTERCLOCKWISE
                   : options.rotation_deg == 180 ? cv::ROTATE_180
                                                 : cv::ROTATE_90_CLOCKWISE);
      }
      if (encoding.valid())
        encoding.get();  // one frame encodes while the next renders
      const double stamp = options.vfr_jitter > 0.0 ? t : -1.0;
      encoding = std::async(
          std::launch::async,
          [&writer, f = std::move(frame), stamp] { writer.Write(f, stamp); });
      progress.Update(k + 1);
    }
    if (encoding.valid()) encoding.get();
    writer.Close();
    progress.Finish();
  } catch (...) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw;
  }
  WriteFileAtomically(options.truth_path, truth);
  const std::string plan_out =
      options.plan_out_path.empty()
          ? (video.parent_path() / (video.stem().string() + ".plan.yaml"))
                .string()
          : options.plan_out_path;
  const fs::path plan_dir = fs::path(plan_out).parent_path();
  WriteFileAtomically(
      plan_out,
      TestPlanToYaml(plan, plan_dir.empty() ? "." : plan_dir.string()));
  fs::rename(temporary, video);
  VideoReaderOptions probe;
  probe.want_luma = probe.want_bgr = false;
  out << fmt::format(
      "rendered {} frames ({:.1f} s) to {}: {}; truth in {}; plan in {}\n",
      frames, frames / options.fps, options.output_path,
      VideoReader(options.output_path, probe).info().Description(),
      options.truth_path, plan_out);
  return 0;
}

}  // namespace softbench
