// Test helper: loads a scene file with the address space capped at its start-up size plus N bytes.
//
// Usage: par2d_load_under_limit SCENE.json EXTRA_BYTES. Exit status: 0 loaded, 2 refused with
// a one-line out_of_memory status, 1 anything else (a crash shows as a signal). A fresh
// process, so that memory freed by earlier tests cannot hide what loading needs.
#include <sys/resource.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "par2d/scene.hpp"

int main(int argc, char** argv) {
  if (argc != 3) return 1;
  std::size_t pages = 0;
  std::ifstream("/proc/self/statm") >> pages;
  rlimit limit{};
  limit.rlim_cur = limit.rlim_max =
      pages * static_cast<std::size_t>(::sysconf(_SC_PAGESIZE)) + std::strtoull(argv[2], nullptr, 10);
  if (::setrlimit(RLIMIT_AS, &limit) != 0) return 1;
  par2d::Scene scene;
  const par2d::Status s = par2d::load_scene_file(argv[1], scene);
  if (s.ok()) return scene.occluders.empty() ? 1 : 0;
  const bool one_line = s.message().find('\n') == std::string::npos && s.message().find("out of memory") != std::string::npos;
  return s.code() == par2d::StatusCode::out_of_memory && one_line ? 2 : 1;
}
