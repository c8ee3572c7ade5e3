#ifndef SOFTBENCH_VISION_TAG_DETECTOR_H_
#define SOFTBENCH_VISION_TAG_DETECTOR_H_

#include <Eigen/Core>
#include <Eigen/LU>
#include <array>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "vision/color_transfer.h"

namespace softbench {

struct TagDetectorOptions {
  // Half length [px] of the profiles taken across the black border's edges,
  // at most 0.45 of a cell (a 25 mm tag36h11 at the thesis's 0.18 mm/px has
  // 17 px cells): long enough to hold a phone's sharpening halos, which
  // reach 2-3 blur radii beyond an edge.
  double edge_half_width_px = 7.0;
  // libapriltag finds the tag's outline in an image decimated by this factor
  // (its bits and our edges are still read at full resolution): 2 is about
  // three times faster on a 1080p frame, and a tag must be ~25 px wide or
  // more per factor to be found.
  float quad_decimate = 2.0f;
  // How the luma's codes encode light (the video's transfer and range,
  // VideoInfo::LumaEncoding): edges are located in linear light. The default
  // is an SDR image's.
  LumaEncoding luma_encoding{};

  std::optional<std::string> Problem() const;
};

// Cells across tag36h11's black border (libapriltag's width_at_border): the
// border is one cell wide, and the six cells inside each side carry data.
// A tag's corners are its black border's outer corners.
inline constexpr int kTagCellsAcross = 8;

// What a tag's border shows of how the camera processed its image (issue
// 28), from the border's edge profiles in linear light. Each is near zero
// for light that the codes encode as the video's metadata says, blurred by
// the lens before it was recorded. The tag's scale does not depend on any
// of them (the border's midlines, CellWhites' gain correction), so they are
// reported, not corrected for again; halos have the dots weighed in codes
// (CameraProcessing::sharpened).
struct TagEdgeSigns {
  // How far each edge of the one-cell black border sits toward its bright
  // side [px]: half the border's measured width less the cell's width. A
  // tone curve the metadata does not name, or blur or sharpening applied
  // to the codes after the curve, moves it (0.1-0.5 px under a phone's).
  double edge_shift_px = 0.0;
  // Sharpening's halos: the larger of the overshoot above the white end and
  // the undershoot below the black end of the outer edges' mean profile, as
  // a fraction of the step, averaged over the four sides.
  double halo = 0.0;
  // The white paper beyond the border against the white data cells inside
  // it, relative, less one: a phone's local tone mapping (which lifts the
  // dark table around the tag) or light falling off across the tag.
  double white_ratio = 0.0;
};

struct TagDetection {
  int id = 0;
  int hamming = 0;  // corrected bit errors
  // Outer corners of the black border, OpenCV pixel convention (pixel centres
  // at integers), in libapriltag's order: counter-clockwise in the printed tag
  // from its bottom-left corner.
  std::array<Eigen::Vector2d, 4> corners;
  // libapriltag's own corners before refinement (same convention).
  std::array<Eigen::Vector2d, 4> coarse_corners;
  // False when an edge was too short or too faint to refine: `corners` are
  // then libapriltag's.
  bool refined = false;
  // From the last fit of the border; nullopt when it was not refined or no
  // white data cell showed the border's inner edge.
  std::optional<TagEdgeSigns> signs;
};

// tag36h11 detection: libapriltag finds tags and decodes ids at full
// resolution; the black border's two edges on each side (the outer one and,
// at its white data cells, the inner one) are then located to sub-pixel
// accuracy and the border's midlines intersected (FitBorderSideOf in
// tag_detector.cc), because libapriltag's corners are off by up to ~0.2 px
// even on exact noise-free renderings, cornerSubPix shrinks anti-aliased
// corners by about as much, and an edge alone moves with whatever the
// camera did to its codes (a tone curve, sharpening, scaling after the
// curve) by up to 0.6 % of the tag's size. Building
// libapriltag's decoding table costs as much as a 1080p detection, so one
// detector serves many frames.
class TagDetector {
 public:
  explicit TagDetector(const TagDetectorOptions& options = {});
  ~TagDetector();
  TagDetector(const TagDetector&) = delete;
  TagDetector& operator=(const TagDetector&) = delete;

  // `gray`: luma, 8 or 16 bits (vision/luma.h).
  std::vector<TagDetection> Detect(const cv::Mat& gray) const;

 private:
  TagDetectorOptions options_;
  struct Apriltag;
  std::unique_ptr<Apriltag> apriltag_;
};

// The outer corners of a tag already known to within a few pixels (the last
// frame's): the border located afresh as TagDetector does. nullopt when an
// outer edge is partly hidden (under 90 % of its profiles have clean black
// and white ends) or not straight (RMS of its points about the line above
// `max_edge_rms_px`): a covered tag is never half-measured.
std::optional<std::array<Eigen::Vector2d, 4>> RefineTagCorners(
    const cv::Mat& gray, const std::array<Eigen::Vector2d, 4>& approximate,
    const TagDetectorOptions& options, double max_edge_rms_px);

// The homography taking the four points `from` exactly to `to`: the eight
// equations of its entries with the last one 1, solved in double precision;
// nullopt when the points are no quadrilateral. (cv::findHomography solves
// the same with a normalisation and a refinement that took a sixth of the
// tag's time in every frame.)
std::optional<Eigen::Matrix3d> HomographyThrough(
    const std::array<Eigen::Vector2d, 4>& from,
    const std::array<Eigen::Vector2d, 4>& to);

// The largest distance between corresponding corners [px].
double LargestCornerMove(const std::array<Eigen::Vector2d, 4>& a,
                         const std::array<Eigen::Vector2d, 4>& b);

// The tag's corners averaged over frames: each frame's corners first moved
// onto `reference` by the shift and roll that fit them best (the camera's
// own small motion since the reference frame), then averaged. A codec's
// errors of a few hundredths of a pixel per corner are alike within a group
// of pictures, so the first frames alone leave the tag's perspective - the
// camera's tilt, a 0.03 px difference between opposite edges on a 135 px
// tag - wrong by a few tenths of a degree; frames spread over the video
// average them out. `frames` must not be empty.
std::array<Eigen::Vector2d, 4> AverageTagCorners(
    const std::array<Eigen::Vector2d, 4>& reference,
    const std::vector<std::array<Eigen::Vector2d, 4>>& frames);

}  // namespace softbench

#endif  // SOFTBENCH_VISION_TAG_DETECTOR_H_
