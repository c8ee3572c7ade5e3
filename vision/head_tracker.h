#ifndef SOFTBENCH_VISION_HEAD_TRACKER_H_
#define SOFTBENCH_VISION_HEAD_TRACKER_H_

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "vision/color_segmentation.h"
#include "vision/dot_centre.h"
#include "vision/dot_search.h"
#include "vision/frame_source.h"
#include "vision/plane_mapping.h"

namespace softbench {

// The dots that mark one head (thesis fig. 4.7).
struct HeadMarkers {
  std::string name;        // for messages
  std::string color_name;  // for messages
  HsvRange color;
  int dots = 3;
  double dot_diameter_mm = 4.0;
  // Dot centres relative to the head centre [mm] (world axes, mean zero).
  std::vector<Eigen::Vector2d> layout_mm;
};

struct HeadTrackerOptions {
  // Segmentation filters; dot_radius_px is set per head from the mapping.
  SegmentationOptions segmentation;
  // How the full image (or a region after a seek) is searched for dots.
  DotSearchOptions search;
  DotCentreOptions centre;
  // Half side of the region searched around a dot's last position, in dot
  // radii: covers half a radius of motion between frames (5 px at 1080p for
  // the thesis's dots; a head settling after a 6 psi step moves < 1 px per
  // frame). A dot that moved further is found again in the full image.
  double search_radius_factor = 1.5;
  // Largest RMS misfit [mm] between a candidate set of dots and the plan's
  // layout (rigid fit): rejects same-colour blobs that are not this head's.
  double layout_tolerance_mm = 0.6;
  // After ForgetPositions (a seek), a head is first searched for around its
  // last dots, their box grown by this many dot radii (the head's travel
  // between two windows), and in the full image only when it is not there.
  double relocate_radius_factor = 6.0;
  // Measure every frame from the full image (no regions): the slow path,
  // for benchmarks and checks.
  bool full_frame_every_frame = false;

  std::optional<std::string> Problem() const;
};

// One dot in one frame. Identities follow the plan's layout order.
struct DotObservation {
  bool found = false;
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();  // luma-refined
  Eigen::Vector2d plane_mm = Eigen::Vector2d::Zero();
  double sigma_px = 0.0;
  // The thesis's method: centroid of the cleaned binary colour mask.
  Eigen::Vector2d binary_pixel = Eigen::Vector2d::Zero();
  Eigen::Vector2d binary_plane_mm = Eigen::Vector2d::Zero();
};

struct HeadObservation {
  int dots_found = 0;
  bool complete = false;  // every dot found
  // Head centre (centre of its dots) on the plane [mm] and in the image;
  // with dots missing, from the found ones and their offsets at the first
  // detection. NaN when no dot was found.
  Eigen::Vector2d position_mm;
  Eigen::Vector2d pixel;
  Eigen::Vector2d binary_position_mm;  // the same from binary centroids
  // 1-sigma of the position from the dots' uncertainties [mm].
  double sigma_mm = 0.0;
  // In-plane rotation since the first detection [rad] (a diagnostic: the
  // model's heads translate).
  double rotation_rad = 0.0;
  // Same-colour blobs the full-image search rejected (size, shape, layout).
  int rejected_blobs = 0;
  bool full_frame = false;  // measured from the full image this frame
  std::string note;         // why dots are missing, when they are
  std::vector<DotObservation> dots;
};

// Finds each head's dots in the first frame from the whole image, then
// follows them in regions around their last positions; a dot lost there is
// searched for in the whole frame, and one that stays lost is reported
// missing (never interpolated).
class HeadTracker {
 public:
  HeadTracker(PlaneMapping mapping, std::vector<HeadMarkers> heads,
              const HeadTrackerOptions& options = {});

  // Measures every head in one frame.
  std::vector<HeadObservation> Measure(const FrameSource& frame);

  // The mapping of the frames measured next: the reference mapping after the
  // camera's motion (BenchRegistration), so positions stay on the bench
  // while the camera moves. Dot sizes keep the reference's scale.
  void SetMapping(const PlaneMapping& mapping) { mapping_ = mapping; }

  // Recomputes an observation of `head` from its dots' pixels through
  // another mapping (plane coordinates, position, rotation, uncertainty),
  // as Measure would have with it; the tracker's state is not touched.
  void Remap(int head, const PlaneMapping& mapping,
             HeadObservation* observation) const;

  // After a seek or a gap: the next frame does not follow the dots from
  // their last positions but detects each head afresh (layout and all),
  // near where it was or else in the full image. Rotation and missing-dot
  // offsets still refer to the first detection.
  void ForgetPositions();

 private:
  // Follows each dot of `head` in a region around its last position.
  void TrackRegions(const FrameSource& frame, int head, HeadObservation* out);
  // Detection of one head in `region` of the frame; false with `note` set
  // when no set of blobs fits the layout.
  bool Detect(const FrameSource& frame, const cv::Rect& region, int head,
              HeadObservation* out);
  // Detection near the head's last dots (after ForgetPositions).
  bool Relocate(const FrameSource& frame, int head, HeadObservation* out);
  // Refines a dot found as `blob_centroid` from the luma, starting at
  // `start`; false with `note` set when the luma fails.
  bool Refine(const FrameSource& frame, int head, int dot,
              const Eigen::Vector2d& blob_centroid,
              const Eigen::Vector2d& start, HeadObservation* out);
  // Plane coordinates, head position, rotation and uncertainty, and the
  // tracking state (first detection, last positions).
  void Finish(int head, HeadObservation* out);
  // The dots' plane coordinates through `mapping`.
  void ToPlane(int head, const PlaneMapping& mapping,
               HeadObservation* out) const;
  // Rotation, position, pixel and uncertainty from the dots' plane
  // coordinates.
  void Locate(int head, const PlaneMapping& mapping,
              HeadObservation* out) const;

  PlaneMapping mapping_;
  std::vector<HeadMarkers> heads_;
  HeadTrackerOptions options_;
  std::vector<double> radius_px_;
  std::vector<std::vector<Eigen::Vector2d>> last_pixels_;  // per head, dot
  std::vector<std::vector<Eigen::Vector2d>> first_offsets_mm_;
  std::vector<std::vector<Eigen::Vector2d>> first_dots_mm_;
  std::vector<Eigen::Vector2d> claimed_;  // dots taken this frame
  bool relocate_ = false;                 // set by ForgetPositions
};

}  // namespace softbench

#endif  // SOFTBENCH_VISION_HEAD_TRACKER_H_
