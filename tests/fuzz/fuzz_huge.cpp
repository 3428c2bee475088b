// libFuzzer target: shapes far larger than the view and huge emissions must render finite, bounded, SIMD agreeing with scalar.
#include <cstdio>
#include <cstdlib>

#include "fuzz/fuzz_huge_checks.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string problem = par2d::fuzz::check_huge_bytes(data, size);
  if (!problem.empty()) {
    par2d::fuzz::ByteReader in(data, size);
    std::fprintf(stderr, "fuzz_huge: %s\nscene:\n%s", problem.c_str(),
                 par2d::scene_to_json(par2d::fuzz::decode_huge_scene(in).scene).c_str());
    std::abort();  // libFuzzer saves the input as a crash file
  }
  return 0;
}
