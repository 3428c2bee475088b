// Library version.
#pragma once

#define PAR2D_VERSION_MAJOR 0
#define PAR2D_VERSION_MINOR 2
#define PAR2D_VERSION_PATCH 0

namespace par2d {
inline constexpr const char* kVersion = "0.2.0";
}
