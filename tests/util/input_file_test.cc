#include "util/input_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <functional>

#include "tests/support/input_error_matchers.h"
#include "tests/support/scratch_directory.h"
#include "util/input_error.h"
#include "util/text_file.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

TEST(CheckInputFile, RefusesWhatIsNotARegularFileOfASaneSize) {
  const fs::path dir = TestScratch().dir() / "softbench_input_file";
  fs::create_directories(dir);
  const std::string fifo = (dir / "fifo").string();
  fs::remove(fifo);
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const std::string big = (dir / "big.yaml").string();
  std::ofstream(big) << std::string(2000, 'x');

  EXPECT_NE(InputErrorOf([] { CheckInputFile("/dev/zero", "test plan"); })
                .find("/dev/zero: is a device, not a regular file; give the "
                      "test plan's path"),
            std::string::npos);
  EXPECT_NE(InputErrorOf([&] {
              CheckInputFile(fifo, "test plan");
            }).find("is a pipe (FIFO)"),
            std::string::npos);
  EXPECT_NE(InputErrorOf([&] {
              CheckInputFile(dir.string(), "test plan");
            }).find("is a folder"),
            std::string::npos);
  EXPECT_NE(InputErrorOf([&] {
              CheckInputFile((dir / "none").string(), "plan");
            }).find("no such plan"),
            std::string::npos);
  EXPECT_NE(InputErrorOf([&] {
              CheckInputFile(big, "test plan", 1000);
            }).find("2000 bytes is too large for a test plan"),
            std::string::npos);
  EXPECT_EQ(CheckInputFile(big, "test plan", 2000), 2000);
}

TEST(FindNonText, NamesTheLineOfLatin1NulAndControlBytes) {
  EXPECT_FALSE(FindNonText("a: 1\ncaf\xC3\xA9: \xE2\x82\xAC\t\r\n"));
  const auto latin1 = FindNonText("a: 1\nb: caf\xE9\n");
  ASSERT_TRUE(latin1);
  EXPECT_EQ(latin1->line, 2);
  EXPECT_NE(latin1->problem.find("0xE9 is not UTF-8"), std::string::npos);
  const auto nul = FindNonText(std::string("a\n\nb\0", 5));
  ASSERT_TRUE(nul);
  EXPECT_EQ(nul->line, 3);
  EXPECT_NE(nul->problem.find("NUL"), std::string::npos);
  EXPECT_TRUE(FindNonText("\x1B[0m"));           // an escape sequence
  EXPECT_TRUE(FindNonText("\xC3"));              // cut short
  EXPECT_TRUE(FindNonText("\xC0\x80"));          // overlong
  EXPECT_TRUE(FindNonText("\xF5\x80\x80\x80"));  // beyond U+10FFFF
}

TEST(ReadTextFile, RefusesATextThatIsNotUtf8WithFileAndLine) {
  const std::string path =
      (TestScratch().dir() / "softbench_latin1.yaml").string();
  std::ofstream(path) << "id: ok\nname: caf\xE9\n";
  EXPECT_NE(InputErrorOf([&] {
              ReadTextFile(path, "test plan", 1 << 20);
            }).find("softbench_latin1.yaml:2: byte 0xE9 is not UTF-8"),
            std::string::npos);
}

}  // namespace
}  // namespace softbench
