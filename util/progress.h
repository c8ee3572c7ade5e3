#ifndef SOFTBENCH_UTIL_PROGRESS_H_
#define SOFTBENCH_UTIL_PROGRESS_H_

#include <cstdint>
#include <memory>
#include <string>

namespace softbench {

// One piece of long work as the program shows it; ends its line when
// destroyed.
class ProgressLine {
 public:
  virtual ~ProgressLine() = default;
  virtual void Update(int64_t done) = 0;
};

// Where progress goes. Libraries never print: they report through
// ProgressBar, and the program installs the one sink that shows it (the
// command line draws bars on stderr: pipelines/commands/stderr_progress.h).
// Without a sink (tests, other programs using the libraries) nothing is
// shown.
class ProgressSink {
 public:
  virtual ~ProgressSink() = default;
  virtual std::unique_ptr<ProgressLine> Begin(const std::string& label,
                                              int64_t total) = 0;
};

// Installs `sink` for the whole process (nullptr: none); not owned.
void SetProgressSink(ProgressSink* sink);

// How far one piece of long work has got: `done` of `total` units. Shown by
// the installed sink when `enabled` (false under --quiet).
class ProgressBar {
 public:
  ProgressBar(const std::string& label, int64_t total, bool enabled);
  ~ProgressBar() = default;
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  void Update(int64_t done) {
    if (line_ != nullptr) line_->Update(done);
  }
  // Ends the bar's line.
  void Finish() { line_.reset(); }

 private:
  std::unique_ptr<ProgressLine> line_;
};

}  // namespace softbench

#endif  // SOFTBENCH_UTIL_PROGRESS_H_
