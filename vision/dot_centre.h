#ifndef SOFTBENCH_VISION_DOT_CENTRE_H_
#define SOFTBENCH_VISION_DOT_CENTRE_H_

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "vision/color_transfer.h"

namespace softbench {

struct DotCentreOptions {
  // The weighting window reaches this far beyond the dot's radius [px]: wide
  // enough for the anti-aliased edge and the codec's ringing, narrow enough
  // to stay on the head (thesis heads leave ~4 px between a dot and a glint).
  double window_margin_px = 2.0;
  // Width of the ring beyond the window whose luma gives the local
  // background (a plane, so lighting gradients do not pull the centre) [px].
  double background_width_px = 2.0;
  // Window re-centrings; each one shrinks the window's pull by the
  // background estimate's error, and the loop stops early below tolerance.
  int max_iterations = 8;
  double tolerance_px = 1e-4;
  // Least |background - dot| difference in linear light (in codes with
  // weigh_codes) [8-bit levels] to trust the centre (a red dot on the thesis's
  // clear resin differs by ~150).
  double min_contrast = 15.0;
  // How the luma's codes encode light (FrameSource::luma_encoding): the
  // coverage weights are taken in linear light, where a pixel's value is
  // linear in how much of it the dot covers; in codes a camera's curve
  // bends that and the centre locks toward pixel centres. The default is an
  // SDR image's.
  LumaEncoding luma_encoding;
  // Weigh the codes as they are, not the light they encode: for codes that
  // were sharpened after the camera's curve (CameraProcessing's halos). An
  // unsharp mask is linear in the codes, so it leaves their centroid where
  // it was, while the light the codes name overshoots and undershoots
  // unevenly about a sharp edge and moves a dot's centre by up to 0.04 px
  // with the pixel grid's phase. The price is the curve's bend of the edge's
  // partly covered pixels, about 0.01 px on a pixel-sharp edge and less
  // under a lens's blur (docs/measurement.md).
  bool weigh_codes = false;

  std::optional<std::string> Problem() const;
};

// A dot centre located from the full-resolution luma.
struct DotCentre {
  bool found = false;
  std::string why_not;                               // when !found
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // pixels, OpenCV
  // 1-sigma uncertainty of each coordinate from the background noise [px].
  double sigma_px = 0.0;
  double contrast = 0.0;     // background - dot luma [levels]
  double noise_level = 0.0;  // RMS background residual [levels]
  int iterations = 0;
};

// Luma-weighted centroid of a dot of radius `radius_px` near `start`.
// Colour locates a dot only to about a pixel (4:2:0 video carries chroma at
// half resolution); the luma contrast between the dot and the head locates
// its edge. Each pixel's weight is its estimated coverage by the dot,
//   w = (background(p) - luma(p)) / (background - dot),
// with the background a plane fitted on a ring outside the dot, inside a
// soft-edged circular window (so the window's own centroid moves smoothly
// with the centre: no pixel locking). The centroid of the coverage is the
// centre of the dot's image; the window is re-centred until it settles.
DotCentre LocateDotCentre(const cv::Mat& luma, const Eigen::Vector2d& start,
                          double radius_px,
                          const DotCentreOptions& options = {});

}  // namespace softbench

#endif  // SOFTBENCH_VISION_DOT_CENTRE_H_
