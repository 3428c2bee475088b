# Build for WebAssembly with emscripten (Debian's `emscripten` package, 3.1.6): the library
# without TBB and without threads (one thread: no pthreads, so no SharedArrayBuffer is needed),
# its C API wrapped as the JavaScript module web/par2d.mjs. The header-only dependencies come
# from the build machine's Debian packages (cmake/Par2dHostHeaders.cmake), never the rest of
# /usr/include. PAR2D_WASM_SIMD (default ON) compiles the SSE4.2 kernel to SIMD128; OFF is the
# scalar-only module. Usage: cmake --preset wasm (docs/platforms.md).
if(NOT DEFINED PAR2D_EMSCRIPTEN_ROOT)
  set(PAR2D_EMSCRIPTEN_ROOT /usr/share/emscripten)
  if(DEFINED ENV{EMSCRIPTEN})
    set(PAR2D_EMSCRIPTEN_ROOT $ENV{EMSCRIPTEN})
  endif()
endif()
include(${PAR2D_EMSCRIPTEN_ROOT}/cmake/Modules/Platform/Emscripten.cmake)

# emcc's JavaScript optimizer runs under node and needs acorn: Debian's node-acorn installs it
# in /usr/share/nodejs, which a node from elsewhere (NodeSource's) does not search.
set(CMAKE_CXX_LINKER_LAUNCHER ${CMAKE_COMMAND} -E env NODE_PATH=/usr/share/nodejs)

# No TBB for WebAssembly, and no std::thread without pthreads: tiles run on the calling thread.
set(PAR2D_USE_TBB OFF CACHE BOOL "" FORCE)

# par2d reports failures as statuses, some of them caught from C++ exceptions (a JSON syntax
# error, an allocation that fails), so exceptions must be caught. WebAssembly's own exception
# handling (node >= 17, every current browser) costs nothing where nothing throws; emscripten's
# older JavaScript-based catching (-fexceptions) routes every call that may throw through
# JavaScript and made the paper.json frame about 20% slower.
set(CMAKE_CXX_FLAGS_INIT "-fwasm-exceptions")
set(CMAKE_EXE_LINKER_FLAGS_INIT "-fwasm-exceptions")
