#include "util/progress.h"

#include <atomic>

namespace softbench {
namespace {

std::atomic<ProgressSink*> g_sink{nullptr};

}  // namespace

void SetProgressSink(ProgressSink* sink) { g_sink.store(sink); }

ProgressBar::ProgressBar(const std::string& label, int64_t total,
                         bool enabled) {
  ProgressSink* sink = g_sink.load();
  if (enabled && sink != nullptr) line_ = sink->Begin(label, total);
}

}  // namespace softbench
