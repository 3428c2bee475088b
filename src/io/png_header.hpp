// The size a PNG file declares, read from its signature and IHDR chunk before anything is
// decoded: the image loaders check it against their limits first, so a tiny file declaring a
// huge image is refused without decoding it.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>

namespace par2d::detail {

// Reads the first 24 bytes of `file` (the signature, then length 13, "IHDR", width, height)
// into `width` and `height` and rewinds it; or says what is wrong with them.
inline std::optional<std::string> read_png_size(std::FILE* file, std::uint32_t& width, std::uint32_t& height) {
  constexpr unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  constexpr unsigned char kIhdr[8] = {0, 0, 0, 13, 'I', 'H', 'D', 'R'};
  unsigned char header[24] = {};
  if (std::fread(header, 1, sizeof header, file) != sizeof header ||
      std::memcmp(header, kSignature, sizeof kSignature) != 0)
    return std::string("not a PNG file");
  if (std::memcmp(header + 8, kIhdr, sizeof kIhdr) != 0) return std::string("not a PNG file (no IHDR header)");
  const auto be32 = [&](int at) {
    return (std::uint32_t{header[at]} << 24) | (std::uint32_t{header[at + 1]} << 16) |
           (std::uint32_t{header[at + 2]} << 8) | std::uint32_t{header[at + 3]};
  };
  width = be32(16);
  height = be32(20);
  std::rewind(file);
  return std::nullopt;
}

}  // namespace par2d::detail
