#ifndef SOFTBENCH_TESTS_PIPELINES_SCRATCH_DIRECTORY_H_
#define SOFTBENCH_TESTS_PIPELINES_SCRATCH_DIRECTORY_H_

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace softbench {

// A fixture with a fresh directory per test (named after the test) for the
// files a command reads and writes.
class ScratchDirectoryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        std::filesystem::temp_directory_path() /
        ("softbench_" +
         std::string(::testing::UnitTest::GetInstance()
                         ->current_test_info()
                         ->test_suite_name()) +
         "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  std::string Path(const std::string& name) const {
    return (dir_ / name).string();
  }
  std::string Write(const std::string& name, const std::string& text) const {
    std::ofstream(Path(name)) << text;
    return Path(name);
  }
  static std::string Read(const std::string& path) {
    std::ifstream stream(path);
    std::stringstream text;
    text << stream.rdbuf();
    return text.str();
  }
  // Runs the built program with `arguments` (shell words after `softbench`);
  // returns its exit code, and its stdout and stderr when asked.
  int RunProgram(const std::string& arguments, std::string* stderr_text,
                 std::string* stdout_text = nullptr) const {
    const std::string out = Path("stdout.txt"), err = Path("stderr.txt");
    const std::string command = std::string(SOFTBENCH_BINARY) + " " +
                                arguments + " > " + out + " 2> " + err;
    const int status = std::system(command.c_str());
    if (stderr_text != nullptr) *stderr_text = Read(err);
    if (stdout_text != nullptr) *stdout_text = Read(out);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  std::filesystem::path dir_;
};

}  // namespace softbench

#endif  // SOFTBENCH_TESTS_PIPELINES_SCRATCH_DIRECTORY_H_
