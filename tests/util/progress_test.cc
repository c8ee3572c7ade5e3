#include "util/progress.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace softbench {
namespace {

// A sink that records what it was told.
class RecordingSink : public ProgressSink {
 public:
  struct Line : ProgressLine {
    Line(RecordingSink* sink, std::string label) : sink(sink), label(label) {}
    ~Line() override { sink->said.push_back(label + " end"); }
    void Update(int64_t done) override {
      sink->said.push_back(label + " " + std::to_string(done));
    }
    RecordingSink* sink;
    std::string label;
  };
  std::unique_ptr<ProgressLine> Begin(const std::string& label,
                                      int64_t total) override {
    said.push_back(label + " of " + std::to_string(total));
    return std::make_unique<Line>(this, label);
  }
  std::vector<std::string> said;
};

TEST(ProgressBar, ReportsToTheInstalledSinkOnlyWhenEnabled) {
  {
    ProgressBar unseen("nobody", 10, true);  // no sink: nothing, no crash
    unseen.Update(5);
  }
  RecordingSink sink;
  SetProgressSink(&sink);
  {
    ProgressBar quiet("quiet", 10, false);
    quiet.Update(5);
    ProgressBar bar("measure", 10, true);
    bar.Update(3);
    bar.Update(10);
    bar.Finish();
    bar.Update(11);  // after Finish: nothing
  }
  SetProgressSink(nullptr);
  EXPECT_EQ(sink.said, (std::vector<std::string>{"measure of 10", "measure 3",
                                                 "measure 10", "measure end"}));
}

}  // namespace
}  // namespace softbench
