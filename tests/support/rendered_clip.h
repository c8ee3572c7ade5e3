#ifndef SOFTBENCH_TESTS_SUPPORT_RENDERED_CLIP_H_
#define SOFTBENCH_TESTS_SUPPORT_RENDERED_CLIP_H_

#include <string>

#include "pipelines/commands/render_command.h"
#include "tests/support/scratch_directory.h"

namespace softbench {

// The options of a quick render of `plan_yaml` (written to plan.yaml) into
// `scratch`: clip.mp4, truth.csv and rendered.plan.yaml, 720p, x264
// veryfast, quiet. A test changes what it needs before RenderClip.
RenderCommandOptions QuickRenderOptions(const ScratchDirectory& scratch,
                                        const std::string& plan_yaml);

// Renders `options`; a render that fails is the test's failure.
void RenderClip(const RenderCommandOptions& options);

}  // namespace softbench

#endif  // SOFTBENCH_TESTS_SUPPORT_RENDERED_CLIP_H_
