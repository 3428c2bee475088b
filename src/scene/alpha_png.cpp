// A PNG's alpha plane (stb_image), for polygons_from_alpha: the size checked from the header before decoding.
#include <stb/stb_image.h>
#include <sys/stat.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <utility>

#include "io/input_file.hpp"
#include "io/png_header.hpp"
#include "par2d/alpha_outline.hpp"

namespace par2d {
namespace {

Status bad_png(const std::string& path, const std::string& what) {
  return Status(StatusCode::invalid_argument, path + ": " + what);
}

}  // namespace

Status load_png_alpha(const std::string& path, AlphaImage& out) {
  try {
    detail::FileHandle file(nullptr, &std::fclose);
    struct stat st {};
    if (Status s = detail::open_regular_file(path, file, st); !s.ok()) return s;
    std::uint32_t declared_width = 0, declared_height = 0;
    if (auto problem = detail::read_png_size(file.get(), declared_width, declared_height)) return bad_png(path, *problem);
    if (declared_width > static_cast<std::uint32_t>(kMaxImageSide) ||
        declared_height > static_cast<std::uint32_t>(kMaxImageSide))
      return bad_png(path, "is " + std::to_string(declared_width) + "x" + std::to_string(declared_height) +
                               ", larger than any image (" + std::to_string(kMaxImageSide) + " per side)");
    int width = 0, height = 0, channels = 0;
    if (!stbi_info_from_file(file.get(), &width, &height, &channels))
      return bad_png(path, std::string("cannot decode the PNG (") + stbi_failure_reason() + ")");
    // stb_image reports a palette or gray image with transparency (tRNS) with its alpha channel.
    if (channels != 2 && channels != 4)
      return bad_png(path, "has no alpha channel (" + std::to_string(channels) +
                               (channels == 1 ? " channel" : " channels") + "): an outline needs gray+alpha or RGBA");
    if (static_cast<std::uint32_t>(width) != declared_width || static_cast<std::uint32_t>(height) != declared_height)
      return bad_png(path, "cannot decode the PNG (its header is inconsistent)");
    std::unique_ptr<unsigned char, void (*)(void*)> pixels(
        stbi_load_from_file(file.get(), &width, &height, &channels, 2), &stbi_image_free);
    if (!pixels) return bad_png(path, std::string("cannot decode the PNG (") + stbi_failure_reason() + ")");
    if (static_cast<std::uint32_t>(width) != declared_width || static_cast<std::uint32_t>(height) != declared_height)
      return bad_png(path, "cannot decode the PNG (its size changed while reading)");
    AlphaImage image;
    image.width = width;
    image.height = height;
    const std::size_t count = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    image.alpha.resize(count);
    for (std::size_t k = 0; k < count; ++k) image.alpha[k] = pixels.get()[2 * k + 1];
    out = std::move(image);
    return Status::success();
  } catch (const std::bad_alloc&) {
    return Status(StatusCode::out_of_memory, path + ": out of memory while loading the PNG");
  }
}

}  // namespace par2d
