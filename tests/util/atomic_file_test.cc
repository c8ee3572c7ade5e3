#include "util/atomic_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/support/input_error_matchers.h"
#include "tests/support/scratch_directory.h"
#include "util/input_error.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

std::string Read(const fs::path& path) {
  std::ifstream stream(path);
  std::stringstream text;
  text << stream.rdbuf();
  return text.str();
}

TEST(WriteFileAtomically, ReplacesTheFileAndLeavesNoTemporary) {
  const fs::path dir = TestScratch().dir() / "softbench_atomic_ok";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path path = dir / "out.csv";
  WriteFileAtomically(path.string(), "old\n");
  WriteFileAtomically(path.string(), "new\n");
  EXPECT_EQ(Read(path), "new\n");
  EXPECT_EQ(
      std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(WriteFileAtomically, FailsWithTheFileNamedWhenTheDirectoryIsMissing) {
  const std::string path = "/nonexistent_softbench_dir/out.csv";
  const std::string message =
      InputErrorOf([&] { WriteFileAtomically(path, "x"); });
  EXPECT_NE(message.find(path), std::string::npos);
}

}  // namespace
}  // namespace softbench
