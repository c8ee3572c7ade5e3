#ifndef SOFTBENCH_PIPELINES_MEASUREMENT_CAMERA_PROCESSING_H_
#define SOFTBENCH_PIPELINES_MEASUREMENT_CAMERA_PROCESSING_H_

#include <Eigen/Core>
#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "vision/rolling_shutter.h"
#include "vision/tag_detector.h"
#include "vision/tag_model.h"

namespace softbench {

// When a sign of the camera's processing, seen on the tag's border
// (TagEdgeSigns, its median over the tag's first frames), is named as an
// effect. Each bar sits several times above what plain footage shows
// (render_test's SceneRenderer.TagBorderShowsTheCamerasProcessing) and
// below what a phone's mildest setting of the stage leaves.
struct CameraProcessingOptions {
  // |edge_shift_px| above this: the codes are not the light the video's
  // transfer names (a tone curve of the phone's, or blur or sharpening
  // applied to the codes). Plain footage: within 0.02 px (a codec's loss
  // at CRF 17-23); an S-curve 1.0 moves edges 0.055 px, --isp 0.19 px.
  double edge_shift_px = 0.03;
  // halo above this (fraction of an edge's step): sharpening. Unencoded,
  // plain frames show 0.2-0.3 % and a phone's mildest sharpening (0.5 px x
  // 0.3) 2.1 %; but a codec rings at edges too: plain footage 0.3-1.0 %
  // (1.0 % under 1 px of lens blur at CRF 17), and that mild sharpening
  // 0.8 %. A phone's strongest (1 px x 1.5 after 1 px of lens blur, under
  // an S-curve 1.0) shows 2.5 % at CRF 10; --isp 5 %.
  double halo = 0.016;
  // |white_ratio| above this: local tone mapping or uneven light. Plain
  // footage under the renderer's lighting fall-off and vignetting: within
  // 0.8 %; local tone mapping 0.3: 2.1-2.4 %.
  double white_ratio = 0.015;
  // The tag's cells [px] under which a tone curve or sharpening on the codes
  // still moves the scale measured from the border's midlines. How far
  // depends on where the edges fall on the pixel grid: single 720p frames
  // (11.2 px cells), an S-curve 0.6 then sharpening 1.5 px x 1.0, measured
  // between -0.51 % and +0.38 % pixel-sharp and -0.21 % and +0.16 % under
  // 0.6 px of lens blur; 1080p (16.8 px), within 0.071 %
  // (docs/measurement.md, "The tag located by its border's midlines").
  // Under it the tag is fitted whole (vision/tag_model.h), which holds
  // those frames within 0.02 % ("Small cells: the tag fitted whole").
  double min_cell_px = 15.0;
  // A rolling shutter, measured from the registration's misfits.
  RollingShutterOptions rolling_shutter;

  std::optional<std::string> Problem() const;
};

// One effect of the camera's processing that the measurement saw, what it
// measured of it and what it does about it.
struct ProcessingEffect {
  std::string name;      // "sharpening halos"
  std::string seen;      // the sign and its size
  std::string handling;  // why the measurement does not move with it
};

// What the video's images show of how the camera processed them (issue 28:
// a phone's sharpening, its own tone curve, local tone mapping, on the
// tag's border; its rolling shutter, in the registration).
struct CameraProcessing {
  bool measured = false;  // false: no tag, or no frame's border showed them
  std::string why_not;    // when !measured
  int frames = 0;         // frames whose border gave the signs
  TagEdgeSigns signs;     // each the median over those frames
  std::vector<ProcessingEffect> effects;  // those above the options' bars
  // Halos above the bar: the codes were sharpened, so the dots are weighed
  // in codes (DotCentreOptions::weigh_codes).
  bool sharpened = false;
  // The tag's cells in the video [px] (its black square's mean side over
  // its 8 cells); NaN without a tag.
  double tag_cell_px = std::numeric_limits<double>::quiet_NaN();
  // The codes were processed (halos or an edge shift above the bars) and
  // the tag's cells are under CameraProcessingOptions::min_cell_px, and
  // the tag fitted whole was not found: the tag's scale may follow the
  // processing.
  bool tag_scale_at_risk = false;
  // CameraProcessingOptions::min_cell_px, when the scale is at risk.
  double tag_cells_wanted_px = 0.0;
  // Where the processing and small cells put the midlines' scale at risk,
  // the tag fitted whole (vision/tag_model.h) on the first frame, and how
  // far it moved the scale from the midlines' (size ratio - 1). Found, its
  // corners replace the midlines' in the plane's mapping, and the scale is
  // no longer at risk.
  std::optional<TagModelFit> tag_model;
  double tag_model_scale_change = 0.0;
  RollingShutter rolling_shutter;  // from the registration
  // One line for a person: the tag border's effects seen by name (or that
  // none was), then its signs, and whether they put the tag's scale at risk.
  std::string Summary() const;
};

// The signs of the tag's frames, combined and named. `frames` may be empty
// (why_not says so).
CameraProcessing DescribeCameraProcessing(
    const std::vector<TagEdgeSigns>& frames,
    const CameraProcessingOptions& options);

// Whether the border's midlines may follow the processing `processing`
// saw: the codes were processed (halos or an edge shift above the bars)
// and the tag's cells, from its corners in the video (any order around the
// square), are under options.min_cell_px.
bool TagScaleAtRisk(const std::array<Eigen::Vector2d, 4>& tag_corners,
                    const CameraProcessingOptions& options,
                    const CameraProcessing& processing);

// Keeps the tag's cell size in `processing`; where its scale is at risk
// (TagScaleAtRisk), says in the handling of each effect on the codes what
// was done: the tag fitted whole (`whole`, with `scale_change` from the
// midlines' size), or, without a fit found, that the scale is at risk.
void NoteTagCells(const std::array<Eigen::Vector2d, 4>& tag_corners,
                  const CameraProcessingOptions& options,
                  const std::optional<TagModelFit>& whole, double scale_change,
                  CameraProcessing* processing);

// Keeps `shutter` in `processing`, and names its shear as an effect when it
// was seen.
void NameRollingShutter(const RollingShutter& shutter,
                        CameraProcessing* processing);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_MEASUREMENT_CAMERA_PROCESSING_H_
