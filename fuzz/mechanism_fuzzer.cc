// Any bytes as a mechanism file: a mechanism or a located InputError.
#include "fuzz/fuzz_input.h"
#include "pipelines/formats/mechanism_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return softbench::ParseOrInputError([&] {
    softbench::ParseMechanismYaml(softbench::AsText(data, size), "m.yaml");
  });
}
