#ifndef SOFTBENCH_PIPELINES_MEASUREMENT_PLAN_CAMERA_H_
#define SOFTBENCH_PIPELINES_MEASUREMENT_PLAN_CAMERA_H_

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "pipelines/formats/test_plan.h"
#include "vision/camera.h"
#include "vision/head_tracker.h"
#include "vision/plane_mapping.h"
#include "vision/video_reader.h"

namespace softbench {

// The camera intrinsics the plan implies for a video of the given size: its
// intrinsics file (checked against the size) or its focal length.
CameraIntrinsics PlanIntrinsics(const TestPlan& plan, int width_px,
                                int height_px);

// Pixels to the dot plane as the plan's calibration says: from its tag
// (median of the corners over the video's first `tag_frames` frames), its
// mm_per_px or the first head's dots. Reads on from the reader's position
// (the video's start). `source` receives a name for it ("tag 0",
// "mm_per_px"); `tag_corners` (optional) the tag's corners the mapping was
// made from. Throws InputError when the plan's scale is not in the video.
PlaneMapping PlanMapping(
    const TestPlan& plan, VideoReader* reader,
    const CameraIntrinsics& intrinsics, int tag_frames, std::string* source,
    std::optional<std::array<Eigen::Vector2d, 4>>* tag_corners = nullptr);

// The plan's heads as the tracker needs them.
std::vector<HeadMarkers> PlanHeadMarkers(const TestPlan& plan);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_MEASUREMENT_PLAN_CAMERA_H_
