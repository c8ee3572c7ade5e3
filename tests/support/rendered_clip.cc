#include "tests/support/rendered_clip.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <filesystem>
#include <functional>
#include <sstream>
#include <vector>

namespace softbench {
namespace {

namespace fs = std::filesystem;

// The running test program's size and modification time, in hex: what
// changes when it is rebuilt.
std::string ProgramStamp() {
  const fs::path program = fs::read_symlink("/proc/self/exe");
  const auto size = fs::file_size(program);
  const auto time = fs::last_write_time(program).time_since_epoch().count();
  std::ostringstream stamp;
  stamp << std::hex << size << "-" << time;
  return stamp.str();
}

// An exclusive lock on `path` (created if missing) for its lifetime.
class FileLock {
 public:
  explicit FileLock(const fs::path& path)
      : fd_(open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644)) {
    if (fd_ < 0 || flock(fd_, LOCK_EX) != 0) {
      ADD_FAILURE() << "cannot lock " << path;
    }
  }
  ~FileLock() {
    if (fd_ >= 0) close(fd_);
  }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_;
};

// What a render writes besides the plan it reads.
std::vector<fs::path> RenderOutputs(const RenderCommandOptions& options) {
  return {options.output_path, options.truth_path, options.plan_out_path};
}

}  // namespace

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

void RenderSharedClip(const RenderCommandOptions& options,
                      const std::string& name) {
  ASSERT_FALSE(options.plan_out_path.empty()) << name;
  const fs::path cache(SOFTBENCH_TEST_CLIP_CACHE);
  fs::create_directories(cache);
  // The plan's text is in the name too, for a suite that edits its plan
  // without a rebuild in between (it cannot, but a stale clip must not be
  // possible at all).
  const std::string plan_text = ReadText(options.plan_path);
  std::ostringstream key;
  key << name << "-" << ProgramStamp() << "-" << std::hex
      << std::hash<std::string>()(plan_text);
  const fs::path ready = cache / key.str();
  const FileLock lock(cache / (name + ".lock"));
  if (!fs::exists(ready)) {
    RenderClip(options);
    if (::testing::Test::HasFatalFailure()) return;
    const fs::path staging = cache / (key.str() + ".partial");
    fs::remove_all(staging);
    fs::create_directories(staging);
    for (const fs::path& output : RenderOutputs(options)) {
      fs::copy_file(output, staging / output.filename());
    }
    // Older programs' clips of this suite are never read again.
    for (const auto& entry : fs::directory_iterator(cache)) {
      const std::string entry_name = entry.path().filename().string();
      if (entry.is_directory() && entry.path() != staging &&
          entry_name.starts_with(name + "-")) {
        fs::remove_all(entry.path());
      }
    }
    fs::rename(staging, ready);
    return;
  }
  for (const fs::path& output : RenderOutputs(options)) {
    fs::copy_file(ready / output.filename(), output,
                  fs::copy_options::overwrite_existing);
  }
}

}  // namespace softbench
