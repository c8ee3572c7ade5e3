// `softbench targets`: the sheets a plan needs, and the mistakes refused.
#include "pipelines/commands/targets_command.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

#include "tests/support/input_error_matchers.h"
#include "tests/support/scratch_directory.h"
#include "util/input_error.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

class TargetsCommandTest : public ScratchDirectoryTest {};

TEST_F(TargetsCommandTest, WritesEverySheetForThePlan) {
  TargetsCommandOptions options;
  options.plan_path = SOFTBENCH_SOURCE_DIR "/samples/floating/plan.yaml";
  options.output_dir = Path("sheets");
  std::ostringstream out;
  ASSERT_EQ(RunTargets(options, out), 0);
  for (const char* name : {"tag", "checkerboard", "dots"}) {
    for (const char* ext : {".pdf", ".svg"}) {
      EXPECT_GT(fs::file_size(Path("sheets/") + name + ext), 1000u)
          << name << ext;
    }
  }
  // The floating plan's tag and the dots of its two heads.
  EXPECT_NE(out.str().find("tag36h11 id 1, 25.0 mm"), std::string::npos)
      << out.str();
  EXPECT_NE(out.str().find("dots (2 heads)"), std::string::npos) << out.str();
  EXPECT_NE(Read(Path("sheets/dots.svg")).find("<svg"), std::string::npos);
}

TEST_F(TargetsCommandTest, RefusesAnUnknownIdColourPaperOrBoard) {
  const auto refusal = [&](TargetsCommandOptions options) -> std::string {
    options.output_dir = Path("sheets");
    std::ostringstream out;
    const std::string message = InputErrorOf([&] { RunTargets(options, out); });
    EXPECT_FALSE(fs::exists(Path("sheets")));
    return message;
    return "accepted";
  };
  TargetsCommandOptions options;
  options.tag_id = 587;
  EXPECT_EQ(refusal(options), "--tag-id: 587 is not a tag36h11 id (0 to 586)");
  options = {};
  options.dot_colors = "red,orange";
  EXPECT_EQ(refusal(options).rfind("--dot-colors: 'orange' is not ", 0), 0u);
  options = {};
  options.paper = "a3";
  EXPECT_EQ(refusal(options), "--paper: 'a3' is not a4 or letter");
  options = {};
  options.board = "9by6";
  EXPECT_EQ(refusal(options).rfind("--board: '9by6' is not", 0), 0u);
  options = {};
  options.tag_mm = 5.0;
  EXPECT_EQ(refusal(options).rfind("--tag-mm: a 5 mm tag is too small", 0), 0u);
}

}  // namespace
}  // namespace softbench
