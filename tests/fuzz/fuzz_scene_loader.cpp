// libFuzzer target: arbitrary bytes into par2d::parse_scene must give a valid scene or a clear refusal.
#include <cstdio>
#include <cstdlib>

#include "fuzz/fuzz_checks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string problem = par2d::fuzz::check_scene_text(data, size);
  if (!problem.empty()) {
    std::fprintf(stderr, "fuzz_scene_loader: %s\n", problem.c_str());
    std::abort();  // libFuzzer saves the input as a crash file
  }
  return 0;
}
