#ifndef SOFTBENCH_VISION_TAG_MODEL_H_
#define SOFTBENCH_VISION_TAG_MODEL_H_

#include <Eigen/Core>
#include <array>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "vision/color_transfer.h"
#include "vision/tag_bitmap.h"

namespace softbench {

// The tag's image fitted whole (issue 28): its known cells, seen through a
// homography, integrated over each pixel with the lens's blur in light,
// lit by a linear gradient, through the video's own curve, then a tone
// curve and unsharp-mask sharpening on the codes that the metadata does not
// name, are fitted to every pixel of the tag at once. Where the border's
// midlines (TagDetector) let a phone's processing of small cells move the
// scale by tenths of a percent, the halos and curves are part of the model
// here, and the corners come out where the light says they are.
struct TagModelOptions {
  // How the luma's codes encode light (the video's curve and range).
  LumaEncoding luma_encoding;
  // Cells of the table around the quiet zone drawn, so that the blur and
  // the sharpening near the tag's edge see what lies beyond it.
  double margin_cells = 2.0;
  // The pixels fitted: those whose point on the tag lies within this many
  // cells of the quiet zone's outer edge on the table, so that the edge is
  // seen from both sides. The table is drawn as one level (its texture is
  // not), so only a strip of it is fitted.
  double beyond_cells = 0.5;
  // Levenberg-Marquardt iterations (Ceres).
  int max_iterations = 100;
  // Tags whose cells are larger than this [px] are not fitted (their
  // midlines hold the scale; the fit's cost grows with the area).
  double max_cell_px = 40.0;

  std::optional<std::string> Problem() const;
};

struct TagModelFit {
  bool found = false;
  std::string why_not;  // when !found
  // The black border's outer corners, as TagDetection::corners.
  std::array<Eigen::Vector2d, 4> corners;
  // The processing fitted with them.
  double lens_blur_px = 0.0;       // Gaussian sigma, in light
  double tone_curve = 0.0;         // S-curve strength on the codes
  double sharpen_radius_px = 0.0;  // unsharp mask's Gaussian sigma
  double sharpen_amount = 0.0;
  double pixel_filter = 0.0;  // side taps of a 3-tap filter in light
  // RMS of the fitted pixels' residuals [8-bit levels], and how many.
  double rms_levels = 0.0;
  int pixels = 0;
  int iterations = 0;
};

// Fits the model of `bitmap` to `luma` (CV_8UC1 or CV_16UC1, vision/luma.h),
// starting from `corners` (a TagDetection's, within a pixel or so).
// Not found where the tag's crop leaves the image, its cells exceed
// options.max_cell_px, or the solver does not converge.
TagModelFit FitTagModel(const cv::Mat& luma, const TagBitmap& bitmap,
                        const std::array<Eigen::Vector2d, 4>& corners,
                        const TagModelOptions& options);

}  // namespace softbench

#endif  // SOFTBENCH_VISION_TAG_MODEL_H_
