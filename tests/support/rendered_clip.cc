#include "tests/support/rendered_clip.h"

#include <gtest/gtest.h>

#include <sstream>

namespace softbench {

RenderCommandOptions QuickRenderOptions(const ScratchDirectory& scratch,
                                        const std::string& plan_yaml) {
  RenderCommandOptions render;
  render.plan_path = scratch.Write("plan.yaml", plan_yaml);
  render.output_path = scratch.Path("clip.mp4");
  render.truth_path = scratch.Path("truth.csv");
  render.plan_out_path = scratch.Path("rendered.plan.yaml");
  render.resolution = "720p";
  render.preset = "veryfast";
  render.quiet = true;
  return render;
}

void RenderClip(const RenderCommandOptions& options) {
  std::ostringstream out;
  ASSERT_EQ(RunRender(options, out), 0) << "rendering " << options.plan_path;
}

}  // namespace softbench
