#ifndef SOFTBENCH_TESTS_SUPPORT_SCRATCH_DIRECTORY_H_
#define SOFTBENCH_TESTS_SUPPORT_SCRATCH_DIRECTORY_H_

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace softbench {

// A folder of its own for one test's (or one suite's) files. It is created
// fresh with mkdtemp, so two suites running at once (the release and the
// asan build, or two ctest jobs) never share a name, and it is named after
// the running test so a kept one is easy to find. It is removed when it goes
// out of scope, unless the test failed: then its path is printed and it is
// kept to look at.
class ScratchDirectory {
 public:
  ScratchDirectory();
  ~ScratchDirectory();
  ScratchDirectory(const ScratchDirectory&) = delete;
  ScratchDirectory& operator=(const ScratchDirectory&) = delete;

  const std::filesystem::path& dir() const { return dir_; }
  // The path of `name` inside the folder (not created).
  std::string Path(const std::string& name) const;
  // Writes `text` to `name` inside the folder; returns its path.
  std::string Write(const std::string& name, const std::string& text) const;

 private:
  std::filesystem::path dir_;
};

// The scratch folder of the running test, made on its first use and removed
// when the test ends (kept when it failed): for tests that are not fixtures
// and helpers that write files.
const ScratchDirectory& TestScratch();

// The whole of a file as text ("" when it cannot be read).
std::string ReadText(const std::string& path);

// Runs the built program with `arguments` (shell words after `softbench`),
// its stdout and stderr sent to files in `scratch`; returns its exit code,
// and the text it printed when asked.
int RunSoftbench(const ScratchDirectory& scratch, const std::string& arguments,
                 std::string* stderr_text, std::string* stdout_text = nullptr);

// A fixture with a fresh scratch folder per test for the files a command
// reads and writes.
class ScratchDirectoryTest : public ::testing::Test {
 protected:
  std::string Path(const std::string& name) const {
    return scratch_.Path(name);
  }
  std::string Write(const std::string& name, const std::string& text) const {
    return scratch_.Write(name, text);
  }
  static std::string Read(const std::string& path) { return ReadText(path); }
  int RunProgram(const std::string& arguments, std::string* stderr_text,
                 std::string* stdout_text = nullptr) const {
    return RunSoftbench(scratch_, arguments, stderr_text, stdout_text);
  }
  const std::filesystem::path& dir() const { return scratch_.dir(); }
  const ScratchDirectory& scratch() const { return scratch_; }

 private:
  ScratchDirectory scratch_;
};

}  // namespace softbench

#endif  // SOFTBENCH_TESTS_SUPPORT_SCRATCH_DIRECTORY_H_
