// Any bytes as a force-log manifest: a manifest or a located InputError.
#include "fuzz/fuzz_input.h"
#include "pipelines/characterisation/force_log_manifest.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  return softbench::ParseOrInputError([&] {
    softbench::ParseForceLogManifest(softbench::AsText(data, size),
                                     "manifest.yaml", "/nonexistent");
  });
}
