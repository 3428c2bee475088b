# Header-only dependencies (xsimd, nlohmann-json, stb) for a cross build to Windows or
# WebAssembly, taken from the build machine's Debian packages. Their directories are linked one
# by one into the build tree, so the cross compiler sees those headers and never the rest of
# /usr/include (glibc's headers would shadow the MinGW runtime's or emscripten's libc). The
# targets get the names the packages' own find modules give them. stb's implementation is
# compiled into par2d here (src/CMakeLists.txt), where a Debian build links it from libstb.
#
# PAR2D_HOST_HEADERS: ON by default when cross-building for Windows or WebAssembly.
# PAR2D_HOST_INCLUDE_DIR: where the packages' headers are (default /usr/include).
if(CMAKE_CROSSCOMPILING AND CMAKE_SYSTEM_NAME MATCHES "^(Windows|Emscripten)$")
  set(PAR2D_HOST_HEADERS_DEFAULT ON)
else()
  set(PAR2D_HOST_HEADERS_DEFAULT OFF)
endif()
option(PAR2D_HOST_HEADERS "Take xsimd, nlohmann-json and stb headers from the build machine (cross builds to Windows)"
       ${PAR2D_HOST_HEADERS_DEFAULT})
set(PAR2D_HOST_INCLUDE_DIR "/usr/include" CACHE PATH "Where PAR2D_HOST_HEADERS finds xsimd/, nlohmann/ and stb/")

if(PAR2D_HOST_HEADERS)
  set(dir "${CMAKE_BINARY_DIR}/host-headers")
  file(MAKE_DIRECTORY "${dir}")
  foreach(sub xsimd nlohmann stb)
    if(NOT IS_DIRECTORY "${PAR2D_HOST_INCLUDE_DIR}/${sub}")
      message(FATAL_ERROR "PAR2D_HOST_HEADERS: ${PAR2D_HOST_INCLUDE_DIR}/${sub} is missing "
                          "(apt-get install libxsimd-dev nlohmann-json3-dev libstb-dev)")
    endif()
    file(CREATE_LINK "${PAR2D_HOST_INCLUDE_DIR}/${sub}" "${dir}/${sub}" SYMBOLIC)
  endforeach()
  add_library(xsimd INTERFACE IMPORTED)
  add_library(nlohmann_json::nlohmann_json INTERFACE IMPORTED)
  add_library(PkgConfig::STB INTERFACE IMPORTED)
  foreach(target xsimd nlohmann_json::nlohmann_json PkgConfig::STB)
    set_target_properties(${target} PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${dir}")
    # As system headers: the project's warning flags are not theirs to meet.
    set_target_properties(${target} PROPERTIES INTERFACE_SYSTEM_INCLUDE_DIRECTORIES "${dir}")
  endforeach()
  message(STATUS "par2d: xsimd, nlohmann-json and stb headers from ${PAR2D_HOST_INCLUDE_DIR} (via ${dir})")
endif()
