// libFuzzer entry point for the .m4d reader (fuzz/fuzz_inputs.h says how an input is read).
#include "fuzz_inputs.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  mesh4d::fuzz::exercise_m4d_reader(data, size);
  return 0;
}
