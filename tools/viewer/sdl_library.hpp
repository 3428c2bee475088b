// SDL2 and SDL2_ttf for the viewer, loaded when `par2d view` starts (dlopen) instead of
// linked into the par2d binary. Linked, every par2d command loaded SDL and the ~60 libraries
// it needs (X11, Wayland, PulseAudio, ALSA, ...) before main: 14 M instructions of dynamic
// linking on each `par2d render` or `par2d bench` (callgrind), and a machine without them
// could not run `par2d render` at all. Only the functions the viewer calls are looked up.
#pragma once

#include <SDL.h>
#include <SDL_ttf.h>

#include <string>

namespace par2d::viewer {

// X(name) for each function the viewer calls, by library. (SDL_ttf's TTF_GetError is a
// macro for SDL_GetError: the viewer calls SDL_GetError.)
#define PAR2D_SDL_FUNCTIONS(X)                                                                                  \
  X(SDL_Init) X(SDL_Quit) X(SDL_GetError) X(SDL_GetCurrentVideoDriver) X(SDL_GetDisplayUsableBounds)          \
  X(SDL_CreateWindow) X(SDL_DestroyWindow) X(SDL_CreateRenderer) X(SDL_DestroyRenderer) X(SDL_CreateTexture) \
  X(SDL_CreateTextureFromSurface) X(SDL_DestroyTexture) X(SDL_LockTexture) X(SDL_UnlockTexture)              \
  X(SDL_SetTextureBlendMode) X(SDL_FreeSurface) X(SDL_PollEvent) X(SDL_WaitEventTimeout) X(SDL_RenderCopy)    \
  X(SDL_RenderDrawLinesF) X(SDL_RenderFillRect) X(SDL_RenderPresent) X(SDL_RenderReadPixels)                  \
  X(SDL_SetRenderDrawBlendMode) X(SDL_SetRenderDrawColor)
#define PAR2D_TTF_FUNCTIONS(X) X(TTF_Init) X(TTF_Quit) X(TTF_OpenFont) X(TTF_CloseFont) X(TTF_RenderUTF8_Blended)

// The functions, each a pointer of the header's own type under the function's own name.
struct SdlLibrary {
#define PAR2D_SDL_POINTER(name) decltype(&::name) name = nullptr;
  PAR2D_SDL_FUNCTIONS(PAR2D_SDL_POINTER)
  PAR2D_TTF_FUNCTIONS(PAR2D_SDL_POINTER)
#undef PAR2D_SDL_POINTER
};

// Loads both libraries (by their stable Linux sonames, libSDL2-2.0.so.0 and
// libSDL2_ttf-2.0.so.0) and every function once per process. False, with a one-line reason
// in `error` naming the library or the function, when one is missing.
bool load_sdl_library(SdlLibrary& sdl, std::string& error);

}  // namespace par2d::viewer
