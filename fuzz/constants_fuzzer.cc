// Any bytes as a constants file: constants or a located InputError.
#include "fuzz/fuzz_input.h"
#include "pipelines/formats/constants_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return softbench::ParseOrInputError([&] {
    softbench::ParseConstantsYaml(softbench::AsText(data, size), "c.yaml");
  });
}
