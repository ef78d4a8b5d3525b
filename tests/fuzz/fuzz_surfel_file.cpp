// libFuzzer target: .surfels bytes through SurfelFileReader (every array read whole) and
// readSurfelFile, as given and with the checksums repaired. Only pbs::InputError may escape.
#include "fuzz_entries.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    pbs::fuzz::readSurfelBytes({data, size});
  } catch (const pbs::InputError&) {
  }
  return 0;
}
