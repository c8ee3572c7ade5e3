#ifndef SOFTBENCH_PIPELINES_MEASUREMENT_DISTORTION_CHECK_H_
#define SOFTBENCH_PIPELINES_MEASUREMENT_DISTORTION_CHECK_H_

#include <string>
#include <vector>

#include "pipelines/formats/test_plan.h"
#include "pipelines/measurement/camera_processing.h"
#include "pipelines/measurement/video_measurement.h"

namespace softbench {

// The dots' spacing through the mapping against the plan's layout over the
// measured frames (every complete head): warns when they differ by more
// than the plan's distortion_tolerance, on average or across the frames,
// and then says which of the two to trust and why: a layout whose shape
// the dots do not have cannot check the scale; a scale that differs across
// the field is the lens; one off alike everywhere is the dots' height, a
// print's size or the lens, which the footage cannot tell apart, unless
// `processing` puts the tag's scale at risk (a phone's processing on a
// small-celled tag), which is then named as the likeliest. The tag's
// scale is kept in every case (the difference is in each change's
// uncertainty, LayoutScaleUncertainty). `scale_source` names the mapping
// in the message; `camera_height_mm` is its camera's height above the tag
// (PlaneMapping::CameraHeightMm, 0 for a mapping from a scale).
DistortionCheck CheckDistortion(const TestPlan& plan,
                                const std::vector<FrameSample>& frames,
                                const std::string& scale_source,
                                double camera_height_mm,
                                const CameraProcessing& processing);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_MEASUREMENT_DISTORTION_CHECK_H_
