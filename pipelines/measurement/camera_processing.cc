#include "pipelines/measurement/camera_processing.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>

#include "util/check.h"
#include "util/statistics.h"

namespace softbench {

namespace {

// The effect NameRollingShutter adds: seen in the registration, not on the
// tag's border.
constexpr char kRollingShutterShear[] = "rolling-shutter shear";
// The effects of processing on the codes, which move the tag's edges.
constexpr char kSharpeningHalos[] = "sharpening halos";
constexpr char kCodesCurve[] =
    "a tone curve or filtering the video's transfer does not describe";

}  // namespace

std::optional<std::string> CameraProcessingOptions::Problem() const {
  if (!(edge_shift_px > 0.0)) return "edge_shift_px must be > 0";
  if (!(halo > 0.0)) return "halo must be > 0";
  if (!(white_ratio > 0.0)) return "white_ratio must be > 0";
  if (!(min_cell_px >= 0.0)) return "min_cell_px must be >= 0";
  if (auto problem = rolling_shutter.Problem()) {
    return "rolling_shutter: " + *problem;
  }
  return std::nullopt;
}

std::string CameraProcessing::Summary() const {
  if (!measured) return "not measured: " + why_not;
  std::vector<std::string> names;
  for (const ProcessingEffect& e : effects) {
    if (e.name != kRollingShutterShear) names.push_back(e.name);
  }
  return fmt::format(
      "{} (over {} frames: edges {:.3f} px toward their {} side, halos "
      "{:.1f} % of the step, the white beyond the border {:+.2f} % against "
      "inside it){}",
      names.empty() ? std::string("no effect of processing seen")
                    : fmt::format("{}", fmt::join(names, "; ")),
      frames, std::abs(signs.edge_shift_px),
      signs.edge_shift_px > 0 ? "bright" : "dark", 100.0 * signs.halo,
      100.0 * signs.white_ratio,
      tag_scale_at_risk
          ? fmt::format("; on the tag's cells of {:.1f} px they may move its "
                        "scale",
                        tag_cell_px)
          : "");
}

CameraProcessing DescribeCameraProcessing(
    const std::vector<TagEdgeSigns>& frames,
    const CameraProcessingOptions& options) {
  SOFTBENCH_CHECK(!options.Problem()) << *options.Problem();
  CameraProcessing out;
  if (frames.empty()) {
    out.why_not = "no frame's tag border showed a white data cell";
    return out;
  }
  out.measured = true;
  out.frames = static_cast<int>(frames.size());
  std::vector<double> shift, halo, white;
  for (const TagEdgeSigns& s : frames) {
    shift.push_back(s.edge_shift_px);
    halo.push_back(s.halo);
    white.push_back(s.white_ratio);
  }
  TagEdgeSigns& signs = out.signs;
  signs.edge_shift_px = Median(shift);
  signs.halo = Median(halo);
  signs.white_ratio = Median(white);
  out.sharpened = signs.halo > options.halo;
  if (out.sharpened) {
    out.effects.push_back(
        {kSharpeningHalos,
         fmt::format("edges overshoot by {:.1f} % of their step",
                     100.0 * signs.halo),
         "the tag is located by its border's midlines, which halos symmetric "
         "about an edge do not move, and each dot by the centroid of its "
         "codes rather than of the light they name: sharpening is linear in "
         "the codes, so it leaves their centroid where it was"});
  }
  if (std::abs(signs.edge_shift_px) > options.edge_shift_px) {
    out.effects.push_back(
        {kCodesCurve,
         fmt::format("every edge sits {:.3f} px toward its {} side, as the "
                     "codes are not the light the transfer names: a phone's "
                     "own tone curve, sharpening or blur applied to the "
                     "codes, or noise clipped at black",
                     std::abs(signs.edge_shift_px),
                     signs.edge_shift_px > 0 ? "bright" : "dark"),
         "the tag is located by its black border's midlines, which both "
         "edges of the one-cell border move apart or together about, so "
         "the scale does not follow the curve"});
  }
  if (std::abs(signs.white_ratio) > options.white_ratio) {
    out.effects.push_back(
        {"local tone mapping or light falling off across the tag",
         fmt::format("the white beyond the border reads {:+.1f} % against "
                     "the white inside it",
                     100.0 * signs.white_ratio),
         "the border's outer edges are moved back by the gain's slope "
         "measured between the two whites"});
  }
  return out;
}

namespace {

double TagCellPx(const std::array<Eigen::Vector2d, 4>& tag_corners) {
  double side_px = 0.0;
  for (int c = 0; c < 4; ++c) {
    side_px += (tag_corners[(c + 1) % 4] - tag_corners[c]).norm() / 4.0;
  }
  return side_px / kTagCellsAcross;
}

}  // namespace

bool TagScaleAtRisk(const std::array<Eigen::Vector2d, 4>& tag_corners,
                    const CameraProcessingOptions& options,
                    const CameraProcessing& processing) {
  const bool codes_processed =
      processing.sharpened ||
      std::abs(processing.signs.edge_shift_px) > options.edge_shift_px;
  return codes_processed && TagCellPx(tag_corners) < options.min_cell_px;
}

void NoteTagCells(const std::array<Eigen::Vector2d, 4>& tag_corners,
                  const CameraProcessingOptions& options,
                  const std::optional<TagModelFit>& whole, double scale_change,
                  CameraProcessing* processing) {
  processing->tag_cell_px = TagCellPx(tag_corners);
  if (!TagScaleAtRisk(tag_corners, options, *processing)) return;
  processing->tag_model = whole;
  const bool fitted = whole && whole->found;
  processing->tag_model_scale_change = fitted ? scale_change : 0.0;
  processing->tag_scale_at_risk = !fitted;
  if (!fitted) processing->tag_cells_wanted_px = options.min_cell_px;
  for (ProcessingEffect& e : processing->effects) {
    if (e.name != kSharpeningHalos && e.name != kCodesCurve) continue;
    if (fitted) {
      e.handling += fmt::format(
          "; but the tag's cells are {:.1f} px in the video, and on cells "
          "under {:.0f} px the midlines still follow the processing, so the "
          "tag was fitted whole: its cells seen through the lens's blur, "
          "the curve and the sharpening, fitted with them to every pixel of "
          "the tag (blur {:.2f} px, a 3-tap filter {:.2f}, tone curve "
          "{:.2f}, sharpening {:.2f} px x {:.2f}, {:.2f} levels RMS), which "
          "moved the scale {:+.3f} % from the midlines'",
          processing->tag_cell_px, options.min_cell_px, whole->lens_blur_px,
          whole->pixel_filter, whole->tone_curve, whole->sharpen_radius_px,
          whole->sharpen_amount, whole->rms_levels, 100.0 * scale_change);
      continue;
    }
    e.handling += fmt::format(
        "; but the tag's cells are {:.1f} px in the video, and on cells "
        "under {:.0f} px the midlines still follow the processing, by as much "
        "as 0.6 % of the scale as the edges fall on the pixel grid{}: "
        "the dots' spacing checks the scale (the layout check), and each "
        "change's uncertainty carries what it finds; print the tag larger, "
        "or film it closer, so that its cells are {:.0f} px or more",
        processing->tag_cell_px, options.min_cell_px,
        whole ? " (fitting the tag whole failed: " + whole->why_not + ")"
              : std::string(),
        options.min_cell_px);
  }
}

void NameRollingShutter(const RollingShutter& shutter,
                        CameraProcessing* processing) {
  processing->rolling_shutter = shutter;
  if (!shutter.seen) return;
  processing->effects.push_back(
      {kRollingShutterShear,
       fmt::format("the sensor's lines were read one after another over "
                   "{:.1f} ± {:.1f} ms, so the camera's motion moved the "
                   "image {:.3f} px RMS between the first line and the last",
                   1e3 * std::abs(shutter.readout_s()),
                   1e3 * shutter.standard_error_s(), shutter.shear_rms_px),
       "each frame's motion is freed of the shear its registration took "
       "up, and each head is measured through the camera's motion when its "
       "line was read: the frame's, moved on by the line's delay times the "
       "camera's image velocity (frames within 8 of the video's ends or a "
       "gap, whose velocity is not known, keep the shear, which a window's "
       "median averages out as the camera trembles back and forth)"});
}

}  // namespace softbench
