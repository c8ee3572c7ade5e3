#include "tests/support/scratch_directory.h"

#include <stdlib.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <vector>

#include "util/check.h"

namespace softbench {
namespace {

// softbench_<suite>_<test>_XXXXXX, with the characters a parameterised
// test's name adds ('/') made safe for a file name.
std::string Template() {
  std::string name = "softbench";
  const ::testing::TestInfo* test =
      ::testing::UnitTest::GetInstance()->current_test_info();
  if (test != nullptr) {
    name += std::string("_") + test->test_suite_name() + "_" + test->name();
  } else if (const ::testing::TestSuite* suite =
                 ::testing::UnitTest::GetInstance()->current_test_suite()) {
    name += std::string("_") + suite->name();
  }
  std::replace(name.begin(), name.end(), '/', '_');
  return (std::filesystem::temp_directory_path() / (name + "_XXXXXX")).string();
}

// Ends the running test's TestScratch folder with the test.
std::unique_ptr<ScratchDirectory>& CurrentTestScratch() {
  static std::unique_ptr<ScratchDirectory> scratch;
  return scratch;
}

class TestScratchCleaner : public ::testing::EmptyTestEventListener {
  void OnTestEnd(const ::testing::TestInfo& /*test*/) override {
    CurrentTestScratch().reset();
  }
};

}  // namespace

const ScratchDirectory& TestScratch() {
  static const bool installed = [] {
    ::testing::UnitTest::GetInstance()->listeners().Append(
        new TestScratchCleaner);
    return true;
  }();
  (void)installed;
  std::unique_ptr<ScratchDirectory>& scratch = CurrentTestScratch();
  if (scratch == nullptr) scratch = std::make_unique<ScratchDirectory>();
  return *scratch;
}

ScratchDirectory::ScratchDirectory() {
  std::string path = Template();
  std::vector<char> buffer(path.begin(), path.end());
  buffer.push_back('\0');
  SOFTBENCH_CHECK(mkdtemp(buffer.data()) != nullptr)
      << "cannot make a scratch folder from " << path;
  dir_ = buffer.data();
}

ScratchDirectory::~ScratchDirectory() {
  if (::testing::Test::HasFailure()) {
    std::cerr << "scratch folder kept: " << dir_.string() << "\n";
    return;
  }
  std::error_code ignored;
  std::filesystem::remove_all(dir_, ignored);
}

std::string ScratchDirectory::Path(const std::string& name) const {
  return (dir_ / name).string();
}

std::string ScratchDirectory::Write(const std::string& name,
                                    const std::string& text) const {
  std::ofstream(Path(name), std::ios::binary) << text;
  return Path(name);
}

std::string ReadText(const std::string& path) {
  std::ifstream stream(path, std::ios::binary);
  std::stringstream text;
  text << stream.rdbuf();
  return text.str();
}

int RunSoftbench(const ScratchDirectory& scratch, const std::string& arguments,
                 std::string* stderr_text, std::string* stdout_text) {
  const std::string out = scratch.Path("stdout.txt");
  const std::string err = scratch.Path("stderr.txt");
  const std::string command = std::string(SOFTBENCH_BINARY) + " " + arguments +
                              " > " + out + " 2> " + err;
  const int status = std::system(command.c_str());
  if (stderr_text != nullptr) *stderr_text = ReadText(err);
  if (stdout_text != nullptr) *stdout_text = ReadText(out);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace softbench
