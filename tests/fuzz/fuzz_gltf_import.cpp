// libFuzzer target: glTF / GLB bytes through the importer, validateScene and analyzeHierarchy.
// Only pbs::InputError may escape the import; anything else (another exception, a crash, a
// sanitizer report, a timeout, an allocation over the limit) is a finding.
#include "fuzz_entries.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    pbs::fuzz::importGltfBytes({data, size});
  } catch (const pbs::InputError&) {
  }
  return 0;
}
