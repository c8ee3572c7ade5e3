// Any bytes as a pressures CSV and as a pressure log (time_s, p1..p3):
// rows or a located InputError.
#include "fuzz/fuzz_input.h"
#include "pipelines/formats/pressure_csv.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = softbench::AsFile(data, size, "pressures.csv");
  for (const bool with_times : {false, true}) {
    softbench::ParseOrInputError([&] {
      softbench::PressureCsvOptions options;
      options.num_actuators = 3;
      options.with_times = with_times;
      if (with_times) options.stated_unit = "psi";  // a plan's unit
      softbench::ReadPressureRows(path, options);
    });
  }
  return 0;
}
