// libFuzzer target: bytes -> input adapter -> whole pipeline -> outputs (see fuzz_entry.h).
// Built and run by `make fuzz` with clang -fsanitize=fuzzer,address,undefined.
#include <cstddef>
#include <cstdint>

#include "fuzz_entry.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  ohm_mirror_detector3d::fuzz::runFuzzInput(data, size);
  return 0;
}
