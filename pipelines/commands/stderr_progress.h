#ifndef SOFTBENCH_PIPELINES_COMMANDS_STDERR_PROGRESS_H_
#define SOFTBENCH_PIPELINES_COMMANDS_STDERR_PROGRESS_H_

#include <memory>
#include <string>

#include "util/progress.h"

namespace softbench {

// The command line's progress bars on stderr: redrawn in place on a terminal
// (at most 10 times a second), one line per 10 % otherwise (logs); nothing
// for work that ends within a second. main installs it (SetProgressSink).
class StderrProgress : public ProgressSink {
 public:
  std::unique_ptr<ProgressLine> Begin(const std::string& label,
                                      int64_t total) override;
};

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_COMMANDS_STDERR_PROGRESS_H_
