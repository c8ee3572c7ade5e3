#include "pipelines/commands/stderr_progress.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace softbench {
namespace {

class StderrProgressLine : public ProgressLine {
 public:
  StderrProgressLine(std::string label, int64_t total)
      : label_(std::move(label)),
        total_(total > 0 ? total : 1),
        terminal_(isatty(STDERR_FILENO) != 0),
        start_(std::chrono::steady_clock::now()),
        last_draw_(start_) {}
  ~StderrProgressLine() override {
    if (drawn_ && terminal_) std::fputc('\n', stderr);
  }

  void Update(int64_t done) override {
    const auto now = std::chrono::steady_clock::now();
    if (now - start_ < std::chrono::seconds(1)) return;
    if (terminal_) {
      if (now - last_draw_ < std::chrono::milliseconds(100) && done < total_)
        return;
    } else {
      const int decile = static_cast<int>(10 * done / total_);
      if (decile == last_decile_) return;
      last_decile_ = decile;
    }
    last_draw_ = now;
    Draw(done, std::chrono::duration<double>(now - start_).count());
  }

 private:
  void Draw(int64_t done, double elapsed_s) {
    const double rate = done / std::max(elapsed_s, 1e-9);
    const double eta = rate > 0 ? (total_ - done) / rate : 0.0;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(kWidth * done / total_);
    std::string bar(filled, '#');
    bar.resize(kWidth, '.');
    std::fprintf(stderr, "%s%s [%s] %3d%% %lld/%lld, %.1f/s, %d:%02d left%s",
                 terminal_ ? "\r" : "", label_.c_str(), bar.c_str(),
                 static_cast<int>(100 * done / total_),
                 static_cast<long long>(done), static_cast<long long>(total_),
                 rate, static_cast<int>(eta) / 60, static_cast<int>(eta) % 60,
                 terminal_ ? "" : "\n");
    std::fflush(stderr);
    drawn_ = true;
  }

  std::string label_;
  int64_t total_;
  bool terminal_;
  bool drawn_ = false;
  int last_decile_ = -1;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace

std::unique_ptr<ProgressLine> StderrProgress::Begin(const std::string& label,
                                                    int64_t total) {
  return std::make_unique<StderrProgressLine>(label, total);
}

}  // namespace softbench
