# Cross build for 64-bit Windows from an x86-64 Debian host with Debian's MinGW-w64
# (g++-mingw-w64-x86-64), no TBB (tiles on std::threads) and the header-only dependencies
# taken from the host's packages (cmake/Par2dHostHeaders.cmake). Runs under wine.
# Usage: cmake --preset x86_64-w64-mingw32, or cmake -S . -B build-mingw
#        -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/x86_64-w64-mingw32.cmake. See docs/platforms.md.
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR x86_64)
set(PAR2D_CROSS_TRIPLET x86_64-w64-mingw32)

# The posix thread model: GCC 12's win32 model has no std::thread or std::mutex.
set(CMAKE_C_COMPILER ${PAR2D_CROSS_TRIPLET}-gcc-posix)
set(CMAKE_CXX_COMPILER ${PAR2D_CROSS_TRIPLET}-g++-posix)
set(CMAKE_RC_COMPILER ${PAR2D_CROSS_TRIPLET}-windres)

# Libraries and packages from the MinGW sysroot only: the host's (TBB among them) are Linux ones.
set(CMAKE_FIND_ROOT_PATH /usr/${PAR2D_CROSS_TRIPLET})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# 64-bit Windows aligns the stack to 16 bytes, and GCC does not realign it for 32- and 64-byte
# AVX stack slots, so an aligned move to one can fault. The assembler writes every aligned
# vector move as its unaligned form (as fast on aligned data). Without it GCC 12 left two such
# moves relative to rsp/rbp in the DLL (they did not fault in the gate's runs).
set(CMAKE_C_FLAGS_INIT "-Wa,-muse-unaligned-vector-move")
set(CMAKE_CXX_FLAGS_INIT "-Wa,-muse-unaligned-vector-move")
# The GCC runtime (libstdc++, libgcc, winpthreads) linked in: par2d's DLL and programs need only
# Windows' own DLLs.
set(CMAKE_EXE_LINKER_FLAGS_INIT "-static")
set(CMAKE_SHARED_LINKER_FLAGS_INIT "-static")

# ctest and the Windows gate run target programs through wine when it is installed.
find_program(PAR2D_WINE NAMES wine wine64 PATHS /usr/lib/wine NO_CMAKE_FIND_ROOT_PATH)
if(PAR2D_WINE)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${PAR2D_WINE})
endif()
