// Normal maps from 8-bit PNG files (stb_image): n = 2 * rgb / 255 - 1 per pixel, image axes.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <new>
#include <string>

#include <stb/stb_image.h>

#include "io/input_file.hpp"
#include "io/png_header.hpp"

#include "par2d/scene.hpp"

namespace par2d {
namespace {

Status bad_map(const std::string& path, const std::string& what) {
  return Status(StatusCode::invalid_scene, path + ": " + what);
}

// n = 2 * c / 255 - 1 per 8-bit component. Out of line with unaliased pointers so that it
// vectorizes: inlined into load_png (whose calls may throw) GCC 12 leaves it scalar.
__attribute__((noinline)) void expand_components(const unsigned char* __restrict src, float* __restrict dst,
                                                 std::size_t count) noexcept {
  for (std::size_t k = 0; k < count; ++k) dst[k] = 2.0f * static_cast<float>(src[k]) / 255.0f - 1.0f;
}

// `width` x `height` > 0: the size the map must have, checked from the header; 0 x 0: any size
// up to kMaxImageSide per side. Nothing is decoded until the header passes.
Status load_png(const std::string& path, NormalMap& out, int expected_width, int expected_height) {
  try {
    detail::FileHandle file(nullptr, &std::fclose);
    struct stat st {};
    if (Status s = detail::open_regular_file(path, file, st); !s.ok()) return s;
    // The size the PNG declares is checked before anything is decoded: a tiny file may declare any size.
    std::uint32_t declared_width = 0, declared_height = 0;
    if (auto problem = detail::read_png_size(file.get(), declared_width, declared_height)) return bad_map(path, *problem);
    const std::string size = std::to_string(declared_width) + "x" + std::to_string(declared_height);
    if (expected_width > 0 && (declared_width != static_cast<std::uint32_t>(expected_width) ||
                               declared_height != static_cast<std::uint32_t>(expected_height))) {
      return bad_map(path, "is " + size + " but the image is " + std::to_string(expected_width) + "x" +
                               std::to_string(expected_height) + " (it must be exactly the image's size)");
    }
    if (declared_width > static_cast<std::uint32_t>(kMaxImageSide) ||
        declared_height > static_cast<std::uint32_t>(kMaxImageSide))
      return bad_map(path, "is " + size + ", larger than any image");
    // stbi_info reads the header chunks only.
    int width = 0, height = 0, channels = 0;
    if (!stbi_info_from_file(file.get(), &width, &height, &channels)) {
      return bad_map(path, std::string("cannot decode the PNG (") + stbi_failure_reason() + ")");
    }
    if (stbi_is_16_bit_from_file(file.get())) return bad_map(path, "a 16-bit PNG; normal maps must be 8-bit RGB");
    // Alpha carries no normal component: an RGBA map is read as RGB. Gray maps cannot hold a normal.
    if (channels != 3 && channels != 4) {
      return bad_map(path, "has " + std::to_string(channels) +
                               (channels == 1 ? " channel" : " channels") + "; normal maps must be 8-bit RGB");
    }
    if (static_cast<std::uint32_t>(width) != declared_width || static_cast<std::uint32_t>(height) != declared_height)
      return bad_map(path, "cannot decode the PNG (its header is inconsistent)");
    std::unique_ptr<unsigned char, void (*)(void*)> pixels(stbi_load_from_file(file.get(), &width, &height, &channels, 3),
                                                           &stbi_image_free);
    if (!pixels) return bad_map(path, std::string("cannot decode the PNG (") + stbi_failure_reason() + ")");
    if (static_cast<std::uint32_t>(width) != declared_width || static_cast<std::uint32_t>(height) != declared_height)
      return bad_map(path, "cannot decode the PNG (its size changed while reading)");
    NormalMap map;
    map.path = path;
    map.width = width;
    map.height = height;
    const std::size_t count = 3 * static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    map.normals.resize(count);
    expand_components(pixels.get(), map.normals.data(), count);
    out = std::move(map);
    return Status::success();
  } catch (const std::bad_alloc&) {
    return Status(StatusCode::out_of_memory, path + ": out of memory while loading the normal map");
  }
}

}  // namespace

Status load_normal_map_png(const std::string& path, NormalMap& out) { return load_png(path, out, 0, 0); }

Status load_normal_map_png(const std::string& path, NormalMap& out, int width, int height) {
  if (width <= 0 || height <= 0 || width > kMaxImageSide || height > kMaxImageSide)
    return Status(StatusCode::invalid_argument, path + ": expected normal map size " + std::to_string(width) + "x" +
                                                    std::to_string(height) + " is not an image size");
  return load_png(path, out, width, height);
}

}  // namespace par2d
