#ifndef SOFTBENCH_VISION_LAYOUT_SCALE_H_
#define SOFTBENCH_VISION_LAYOUT_SCALE_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "vision/camera.h"
#include "vision/dot_centre.h"
#include "vision/frame_source.h"
#include "vision/head_tracker.h"

namespace softbench {

struct LayoutScale {
  bool found = false;
  std::string why_not;  // when !found
  double mm_per_px = 0.0;
  // RMS misfit of the dots' distances to the layout's after scaling,
  // relative to the mean distance.
  double misfit = 0.0;
};

// Every pairwise distance between `points`, sorted ascending.
std::vector<double> PairDistances(const std::vector<Eigen::Vector2d>& points);

// The scale of the dot plane without a tag (thesis 4.1.3 used a measured
// pixel-to-mm factor): a head's dots a known distance apart (its plan
// layout) in one frame. The dot size is estimated from the colour mask, the
// set of blobs whose distances best match the layout's up to scale is
// chosen, centres are refined from the luma, and the scale is the ratio of
// the summed layout distances to the summed image distances (distortion
// removed with the intrinsics). Assumes the camera faces the plane.
LayoutScale MeasureLayoutScale(const FrameSource& frame,
                               const HeadMarkers& head,
                               const CameraIntrinsics& intrinsics,
                               const DotCentreOptions& centre_options = {});

}  // namespace softbench

#endif  // SOFTBENCH_VISION_LAYOUT_SCALE_H_
