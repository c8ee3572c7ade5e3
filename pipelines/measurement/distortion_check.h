#ifndef SOFTBENCH_PIPELINES_MEASUREMENT_DISTORTION_CHECK_H_
#define SOFTBENCH_PIPELINES_MEASUREMENT_DISTORTION_CHECK_H_

#include <string>
#include <vector>

#include "pipelines/formats/test_plan.h"
#include "pipelines/measurement/video_measurement.h"

namespace softbench {

// The distortion check over measured frames (every complete head): warns
// when the dots' spacing through the mapping departs from the plan's layout
// by more than the plan's distortion_tolerance, on average or across the
// frames. `scale_source` names the mapping in the message.
DistortionCheck CheckDistortion(const TestPlan& plan,
                                const std::vector<FrameSample>& frames,
                                const std::string& scale_source);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_MEASUREMENT_DISTORTION_CHECK_H_
