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

// RenderClip for a suite whose every test needs the same clip. ctest runs
// each test in a process of its own, so a suite's SetUpTestSuite would
// render once per test (minutes each under AddressSanitizer). Instead the
// first process renders into a folder of the build named `name` and the
// test program's size and time, under a lock (ctest's parallel jobs wait
// rather than render twice), and every process copies the video, truth and
// rendered plan from there to `options`' paths. A rebuilt test program
// renders afresh, so a changed renderer is never hidden behind an old clip.
// The plan must name its mechanism, not a file beside it: the rendered plan
// is copied, not rewritten for its new folder.
void RenderSharedClip(const RenderCommandOptions& options,
                      const std::string& name);

}  // namespace softbench

#endif  // SOFTBENCH_TESTS_SUPPORT_RENDERED_CLIP_H_
