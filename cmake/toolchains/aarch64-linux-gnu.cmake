# Cross build for 64-bit ARM Linux from an x86-64 Debian host: Debian's cross compiler
# (crossbuild-essential-arm64) and multiarch :arm64 packages (libtbb-dev:arm64 etc.).
# Usage: cmake --preset aarch64-linux-gnu, or cmake -S . -B build-arm64
#        -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/aarch64-linux-gnu.cmake. See docs/arm64.md.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(PAR2D_CROSS_TRIPLET aarch64-linux-gnu)

set(CMAKE_C_COMPILER ${PAR2D_CROSS_TRIPLET}-gcc)
set(CMAKE_CXX_COMPILER ${PAR2D_CROSS_TRIPLET}-g++)

# Debian multiarch: the :arm64 libraries and their CMake/pkg-config files live under
# /usr/lib/aarch64-linux-gnu, next to the host's; headers are shared in /usr/include.
# Setting the library architecture makes find_package/find_library look there (and not in
# the host's /usr/lib/x86_64-linux-gnu).
set(CMAKE_LIBRARY_ARCHITECTURE ${PAR2D_CROSS_TRIPLET})
set(CMAKE_FIND_ROOT_PATH /usr/${PAR2D_CROSS_TRIPLET})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
# pkg-config (for stb) must read the target's .pc files only.
set(ENV{PKG_CONFIG_LIBDIR} "/usr/lib/${PAR2D_CROSS_TRIPLET}/pkgconfig:/usr/share/pkgconfig")
set(ENV{PKG_CONFIG_PATH} "")

# ctest runs target binaries through user-mode emulation when qemu-user is installed. No -L
# sysroot: the :arm64 packages bring libc6:arm64, whose loader /lib/ld-linux-aarch64.so.1 must
# be the one that runs, since it finds that libc first. (With -L /usr/aarch64-linux-gnu the
# cross sysroot's loader, from libc6-arm64-cross, would load the multiarch libc of a different
# build, and threaded programs hang in pthread_create.)
find_program(PAR2D_QEMU_AARCH64 qemu-aarch64)
if(PAR2D_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${PAR2D_QEMU_AARCH64})
endif()
