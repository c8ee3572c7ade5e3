// Any bytes as a test plan: a plan or a located InputError, nothing else.
#include "fuzz/fuzz_input.h"
#include "pipelines/formats/test_plan.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return softbench::ParseOrInputError([&] {
    softbench::ParseTestPlan(softbench::AsText(data, size), "plan.yaml");
  });
}
