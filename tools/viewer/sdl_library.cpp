#include "sdl_library.hpp"

#include <dlfcn.h>

namespace par2d::viewer {

namespace {

// dlopen's reason for the last failure, or a fallback.
std::string dl_reason() {
  const char* reason = dlerror();
  return reason != nullptr ? reason : "unknown reason";
}

// Looks up `name` in `library` into `slot` (of the header's pointer type).
template <class Pointer>
bool look_up(void* library, const char* library_name, const char* name, Pointer& slot, std::string& error) {
  dlerror();  // clears any earlier failure
  void* address = dlsym(library, name);
  if (address == nullptr) {
    error = std::string("cannot find ") + name + " in " + library_name + ": " + dl_reason();
    return false;
  }
  // POSIX guarantees that a dlsym address converts to a function pointer.
  slot = reinterpret_cast<Pointer>(address);
  return true;
}

}  // namespace

bool load_sdl_library(SdlLibrary& sdl, std::string& error) {
  static constexpr const char* kSdl = "libSDL2-2.0.so.0";
  static constexpr const char* kTtf = "libSDL2_ttf-2.0.so.0";
  // Kept loaded until exit: the viewer runs once per process.
  void* sdl_handle = dlopen(kSdl, RTLD_NOW | RTLD_LOCAL);
  if (sdl_handle == nullptr) {
    error = std::string("cannot load ") + kSdl + " (the viewer needs SDL2, package libsdl2-2.0-0): " + dl_reason();
    return false;
  }
  void* ttf_handle = dlopen(kTtf, RTLD_NOW | RTLD_LOCAL);
  if (ttf_handle == nullptr) {
    error = std::string("cannot load ") + kTtf + " (the viewer needs SDL2_ttf, package libsdl2-ttf-2.0-0): " +
            dl_reason();
    return false;
  }
#define PAR2D_SDL_LOOK_UP(name) \
  if (!look_up(sdl_handle, kSdl, #name, sdl.name, error)) return false;
#define PAR2D_TTF_LOOK_UP(name) \
  if (!look_up(ttf_handle, kTtf, #name, sdl.name, error)) return false;
  PAR2D_SDL_FUNCTIONS(PAR2D_SDL_LOOK_UP)
  PAR2D_TTF_FUNCTIONS(PAR2D_TTF_LOOK_UP)
#undef PAR2D_SDL_LOOK_UP
#undef PAR2D_TTF_LOOK_UP
  return true;
}

}  // namespace par2d::viewer
