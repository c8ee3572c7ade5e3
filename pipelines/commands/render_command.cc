#include "pipelines/commands/render_command.h"

#include <fmt/format.h>

#include <filesystem>
#include <vector>

#include "pipelines/commands/common_flags.h"
#include "pipelines/commands/model_flags.h"
#include "pipelines/commands/render_flags.h"
#include "pipelines/synthetic/render_timeline.h"
#include "pipelines/synthetic/render_video.h"
#include "util/atomic_file.h"
#include "util/input_error.h"
#include "vision/video_codecs.h"
#include "vision/video_reader.h"

namespace softbench {

namespace fs = std::filesystem;
namespace {

// One flag per line, each with its help: long lists, not long algorithms.

// What render reads and writes.
void AddRenderFileFlags(CLI::App* c, RenderCommandOptions* options) {
  AddPlanOption(c, &options->plan_path);
  AddOutOption(c, &options->output_path,
               "video to write (.mp4, or .mov for QuickTime)")
      ->required();
  c->add_option("--truth", options->truth_path, "per-frame truth CSV to write")
      ->required();
  c->add_option("--plan-out", options->plan_out_path,
                "the plan with the times used (default: VIDEO.plan.yaml)");
}

// The video's size, codec and quality.
void AddRenderEncoderFlags(CLI::App* c, RenderCommandOptions* options) {
  c->add_option("--resolution", options->resolution, "720p, 1080p, 4k or WxH")
      ->capture_default_str();
  c->add_option("--codec", options->codec, VideoCodecNames())
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
}

// The camera, the scene and the sensor's noise.
void AddRenderSceneFlags(CLI::App* c, RenderCommandOptions* options) {
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
  c->add_flag("--isp", options->processing.isp,
              "a phone's image pipeline: lens blur 0.6 px, RGGB Bayer with "
              "edge-aware demosaicing and raw noise (6000 e- full well, 2 e- "
              "read), S tone curve 0.6, local tone mapping 0.3, temporal "
              "noise reduction 0.5, sharpening 1,0.8; the flags below "
              "override each stage");
  c->add_option("--lens-blur", options->processing.lens_blur_px,
                "the lens's blur in light: a Gaussian's sigma [px] (default "
                "0)");
  c->add_option("--bayer", options->processing.bayer,
                "an RGGB colour filter on the sensor, demosaiced: bilinear or "
                "edge-aware");
  c->add_option("--sensor-full-well", options->processing.sensor_full_well_e,
                "electrons at white on the Bayer sensor: its shot noise (0: "
                "none)");
  c->add_option("--sensor-read-noise", options->processing.sensor_read_noise_e,
                "the Bayer sensor's read noise [electrons]");
  c->add_option("--sensor-scale", options->render.sensor_scale,
                "sensor pixels per video pixel side (1-4): the scene is drawn, "
                "filtered and demosaiced there and scaled down by area")
      ->capture_default_str();
  c->add_option("--tone-curve", options->processing.tone_curve,
                "strength 0..1 of the phone's S tone curve on the codes, "
                "which the metadata does not name (default 0)");
  c->add_option("--local-tone", options->processing.local_tone,
                "strength 0..1 of the phone's local tone mapping: a smooth "
                "gain from each region's brightness (default 0)");
  c->add_option("--temporal-denoise", options->processing.temporal_denoise,
                "strength 0..0.95 of temporal noise reduction on still "
                "regions: the previous frame's weight (default 0)");
  c->add_option("--sharpen", options->processing.sharpen,
                "unsharp-mask sharpening on the codes: RADIUS_PX,AMOUNT "
                "(e.g. 1,0.8)");
  c->add_option("--supersampling", options->render.supersampling,
                "subsamples per pixel side on edges")
      ->capture_default_str();
  c->add_flag("--no-motion-blur", options->no_motion_blur,
              "sharp frames while moving");
  c->add_flag("--tube", options->render.red_tube,
              "add a red air tube distractor");
  c->add_flag("--glint", options->render.glint,
              "add a specular glint on each head");
}

// A phone on a tripod (docs/rendering.md, "Real footage"): its motion,
// exposure and white balance, and what happens at the bench.
void AddRenderBenchFlags(CLI::App* c, RenderCommandOptions* options) {
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
}

// The phone's stream: bit depth, chroma, range, HDR, rotation and frame rate.
void AddRenderPhoneFlags(CLI::App* c, RenderCommandOptions* options) {
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
  c->add_option("--rolling-shutter-ms", options->rolling_shutter_ms,
                "a rolling shutter: ms from the sensor's first line to its "
                "last (a phone: 10-30), so tremor shears the frame")
      ->capture_default_str();
  c->add_option("--vfr-jitter", options->vfr_jitter,
                "variable frame rate: each frame's time moves by up to this "
                "fraction of the frame interval (0-0.9), on a 600 Hz clock "
                "as iPhones write")
      ->capture_default_str();
}

}  // namespace

void AddRenderCommand(CLI::App* c, RenderCommandOptions* options) {
  AddRenderFileFlags(c, options);
  AddRenderEncoderFlags(c, options);
  AddRenderSceneFlags(c, options);
  AddRenderBenchFlags(c, options);
  AddRenderPhoneFlags(c, options);
}

namespace {

constexpr double kMaxRenderFrames = 300000.0;

// The camera and scene of --resolution, --focal-*, --principal-point,
// --tilt-deg, --distortion, the phone's processing, --no-motion-blur and
// --no-ring.
RenderOptions SceneFromFlags(const RenderCommandOptions& flags) {
  const cv::Size size = ParseResolution(flags.resolution);
  if (!(flags.focal_35mm > 0.0)) throw InputError("--focal-35mm: must be > 0");
  if (!(flags.focal_px >= 0.0 && flags.focal_px <= 1e6)) {
    throw InputError("--focal-px: must be > 0 and at most 1e6 px");
  }
  RenderOptions scene = flags.render;
  scene.intrinsics = CameraIntrinsics::FromEquivalentFocalLength(
      flags.focal_35mm, size.width, size.height);
  if (flags.focal_px > 0.0) {
    scene.intrinsics.fx_px = scene.intrinsics.fy_px = flags.focal_px;
  }
  if (!flags.principal_point.empty()) {
    const std::vector<double> c =
        ParseNumberList(flags.principal_point, "--principal-point");
    if (c.size() != 2) throw InputError("--principal-point: give cx,cy");
    scene.intrinsics.cx_px = c[0];
    scene.intrinsics.cy_px = c[1];
  }
  if (!flags.tilt_deg.empty()) {
    const std::vector<double> tilt =
        ParseNumberList(flags.tilt_deg, "--tilt-deg");
    if (tilt.size() != 2) throw InputError("--tilt-deg: give two angles, x,y");
    scene.tilt_x_deg = tilt[0];
    scene.tilt_y_deg = tilt[1];
  }
  if (!flags.distortion.empty()) {
    const std::vector<double> d =
        ParseNumberList(flags.distortion, "--distortion");
    if (d.size() != 5) throw InputError("--distortion: give k1,k2,p1,p2,k3");
    std::copy(d.begin(), d.end(), scene.intrinsics.distortion.begin());
  }
  ApplyPhoneProcessing(flags.processing, &scene);
  scene.motion_blur = !flags.no_motion_blur;
  scene.ring = !flags.no_ring;
  scene.sixteen_bit = flags.bit_depth > 8;
  if (auto problem = scene.Problem()) throw InputError("render: " + *problem);
  return scene;
}

// The tripod of --camera-drift-px and --camera-bump (and the conditions'
// own flags), seeded by --seed.
BenchConditionsOptions ConditionsFromFlags(const RenderCommandOptions& flags) {
  BenchConditionsOptions conditions = flags.conditions;
  if (!flags.camera_drift_px.empty()) {
    const std::vector<double> d =
        ParseNumberList(flags.camera_drift_px, "--camera-drift-px");
    if (d.size() != 2) throw InputError("--camera-drift-px: give dx,dy");
    conditions.drift_px = {d[0], d[1]};
  }
  for (const std::string& bump : flags.camera_bumps) {
    conditions.bumps.push_back(ParseCameraBump(bump));
  }
  conditions.seed = flags.render.seed;
  if (auto problem = conditions.Problem())
    throw InputError("render: " + *problem);
  return conditions;
}

// The phone's video: codec and quality flags, --bit-depth, --chroma,
// --full-range, --hdr, --rotation and --vfr-jitter's clock.
VideoWriterOptions WriterFromFlags(const RenderCommandOptions& flags) {
  VideoWriterOptions writer;
  writer.codec = flags.codec;
  writer.crf = flags.crf;
  writer.bitrate_mbps = flags.bitrate_mbps;
  writer.preset = flags.preset;
  writer.fps = flags.fps;
  writer.keyframe_interval_s = flags.keyframe_interval_s;
  writer.bit_depth = flags.bit_depth;
  writer.chroma = flags.chroma;
  writer.full_range = flags.full_range;
  writer.rotation_deg = flags.rotation_deg;
  if (!flags.hdr.empty()) {
    if (flags.hdr != "hlg" && flags.hdr != "pq") {
      throw InputError("--hdr: '" + flags.hdr + "' is not hlg or pq");
    }
    if (flags.bit_depth < 10) {
      throw InputError("--hdr: HDR needs --bit-depth 10 or 12");
    }
    writer.encoding = {flags.hdr == "hlg" ? Transfer::kHlg : Transfer::kPq,
                       Primaries::kBt2020};
  }
  if (flags.rotation_deg != 0 && flags.rotation_deg != 90 &&
      flags.rotation_deg != 180 && flags.rotation_deg != 270) {
    throw InputError("--rotation: must be 0, 90, 180 or 270");
  }
  if (!(flags.vfr_jitter >= 0.0 && flags.vfr_jitter <= 0.9)) {
    throw InputError("--vfr-jitter: must be between 0 and 0.9");
  }
  if (flags.vfr_jitter > 0.0) writer.time_base_hz = kPhoneClockHz;
  if (auto problem = writer.Problem()) throw InputError("render: " + *problem);
  return writer;
}

}  // namespace

int RunRender(RenderCommandOptions options, std::ostream& out) {
  const TestPlan plan = LoadTestPlan(options.plan_path);
  // The frames' times and truth are held for the whole video: a plan that
  // runs for days is refused with its length, not left to fail allocating.
  const double duration_s = RenderedDurationS(plan);
  if (!(duration_s * options.fps <= kMaxRenderFrames)) {
    throw InputError(fmt::format(
        "{}: the video would last {:.4g} s, {:.3g} frames at {} fps; render "
        "at most {:.0f} frames (about {:.1f} h at 30 fps): shorten "
        "scene.hold_s and scene.rest_s, or the tests' times",
        plan.path, duration_s, duration_s * options.fps, options.fps,
        kMaxRenderFrames, kMaxRenderFrames / 30.0 / 3600.0));
  }
  RenderVideoOptions render;
  render.scene = SceneFromFlags(options);
  render.conditions = ConditionsFromFlags(options);
  render.writer = WriterFromFlags(options);
  render.vfr_jitter = options.vfr_jitter;
  if (!(options.rolling_shutter_ms >= 0.0 &&
        options.rolling_shutter_ms <= 1000.0 / options.fps)) {
    throw InputError(fmt::format(
        "--rolling-shutter-ms: must be between 0 and one frame interval "
        "({:.4g} ms at {} fps)",
        1000.0 / options.fps, options.fps));
  }
  render.readout_s = options.rolling_shutter_ms / 1000.0;
  render.temporal_denoise = TemporalDenoiseFromFlags(options.processing);
  render.progress = !options.quiet;
  if (auto problem = render.Problem()) throw InputError("render: " + *problem);
  const fs::path video(options.output_path);
  const std::string plan_out =
      options.plan_out_path.empty()
          ? (video.parent_path() / (video.stem().string() + ".plan.yaml"))
                .string()
          : options.plan_out_path;
  // The container follows the extension (VideoWriter): a video named .txt
  // or without an extension is a slip, not a wish.
  const std::string extension = video.extension().string();
  if (extension != ".mp4" && extension != ".mov" && extension != ".m4v") {
    throw InputError("--out: " + options.output_path +
                     ": a video is written as .mp4, .mov or .m4v; name it so");
  }
  CheckOutputFile(options.output_path, "--out");
  CheckOutputFile(options.truth_path, "--truth");
  CheckOutputFile(plan_out, "--plan-out");
  CheckOutputsSpareInputs({{"--plan", options.plan_path}},
                          {{"--out", options.output_path},
                           {"--truth", options.truth_path},
                           {options.plan_out_path.empty()
                                ? "--plan-out (by default VIDEO.plan.yaml)"
                                : "--plan-out",
                            plan_out}},
                          {});
  const RenderedVideo rendered = RenderVideo(plan, options.output_path, render);
  WriteFileAtomically(options.truth_path, rendered.truth_csv);
  const fs::path plan_dir = fs::path(plan_out).parent_path();
  WriteFileAtomically(
      plan_out, TestPlanToYaml(rendered.plan,
                               plan_dir.empty() ? "." : plan_dir.string()));
  VideoReaderOptions probe;
  probe.want_luma = probe.want_bgr = false;
  out << fmt::format(
      "rendered {} frames ({:.1f} s) to {}: {}; truth in {}; plan in {}\n",
      rendered.frames, rendered.duration_s, options.output_path,
      VideoReader(options.output_path, probe).info().Description(),
      options.truth_path, plan_out);
  return 0;
}

}  // namespace softbench
