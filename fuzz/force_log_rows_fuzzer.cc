// Any bytes as one test's force log and as a combined log: statistics or a
// located InputError, with bad rows counted and skipped.
#include <atomic>
#include <vector>

#include "calibration/force_log_reader.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace softbench;
  const std::string path = AsFile(data, size, "forces.csv");
  const ForceLogColumns columns;  // time_s, pressure_kpa, +fz_n, +fy_n
  ParseOrInputError([&] {
    ForceTest test;
    ForceLogReadSummary summary;
    std::vector<ForceRow> kept;
    ReadForceTestCsv(path, columns, ForceLogReadOptions(), 0, &test, &summary,
                     &kept, nullptr);
  });
  ParseOrInputError([&] {
    ForceLogReadSummary summary;
    std::vector<ForceRow> kept;
    ReadCombinedForceLog(path, columns, ForceLogReadOptions(), &summary, &kept,
                         nullptr);
  });
  return 0;
}
