#include "util/file_digest.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "tests/support/input_error_matchers.h"
#include "tests/support/scratch_directory.h"
#include "util/input_error.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

std::string WriteFile(const std::string& name, const std::string& bytes) {
  const fs::path path = TestScratch().dir() / name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path.string();
}

// FIPS 180-2's examples, and a file of several read blocks.
TEST(Sha256OfFile, MatchesTheStandardsVectors) {
  EXPECT_EQ(Sha256OfFile(WriteFile("softbench_sha_empty", "")),
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(Sha256OfFile(WriteFile("softbench_sha_abc", "abc")),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(Sha256OfFile(
                WriteFile("softbench_sha_million", std::string(1000000, 'a'))),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  EXPECT_EQ(Sha256OfFile(
                WriteFile("softbench_sha_blocks", std::string(3000000, 'a'))),
            "2a152c894398719c0570f83fac34ac03a0f6e8e474b995c2403aa5434f7b9dd4");
}

TEST(Sha256OfFile, NamesAFileItCannotRead) {
  const std::string message =
      InputErrorOf([&] { Sha256OfFile("/nonexistent/softbench.mp4"); });
  EXPECT_EQ(message.rfind("/nonexistent/softbench.mp4: ", 0), 0u) << message;
}

// A device would be read forever (issue 30: validate /dev/zero hung).
TEST(Sha256OfFile, RefusesADevice) {
  const std::string message = InputErrorOf([&] { Sha256OfFile("/dev/zero"); });
  EXPECT_NE(message.find("/dev/zero: is a device"), std::string::npos)
      << message;
}

// Once the work it runs beside has failed, a large file is not read on.
TEST(Sha256OfFile, StopsWhenAsked) {
  const std::atomic<bool> stop{true};
  EXPECT_EQ(Sha256OfFile(WriteFile("softbench_sha_stop", "abc"), &stop),
            std::nullopt);
}

}  // namespace
}  // namespace softbench
