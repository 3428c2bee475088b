// Normal maps from 8-bit PNG files (stb_image): n = 2 * rgb / 255 - 1 per pixel, image axes.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <new>
#include <string>

#include <stb/stb_image.h>

#include "io/input_file.hpp"

#include "par2d/scene.hpp"

namespace par2d {
namespace {

constexpr unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};

Status bad_map(const std::string& path, const std::string& what) {
  return Status(StatusCode::invalid_scene, path + ": " + what);
}

}  // namespace

Status load_normal_map_png(const std::string& path, NormalMap& out) {
  try {
    detail::FileHandle file(nullptr, &std::fclose);
    struct stat st {};
    if (Status s = detail::open_regular_file(path, file, st); !s.ok()) return s;
    unsigned char signature[8] = {};
    if (std::fread(signature, 1, sizeof signature, file.get()) != sizeof signature ||
        std::memcmp(signature, kPngSignature, sizeof signature) != 0) {
      return bad_map(path, "not a PNG file");
    }
    std::rewind(file.get());
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
    if (width > kMaxImageSide || height > kMaxImageSide) {
      return bad_map(path, "is " + std::to_string(width) + "x" + std::to_string(height) + ", larger than any image");
    }
    std::unique_ptr<unsigned char, void (*)(void*)> pixels(stbi_load_from_file(file.get(), &width, &height, &channels, 3),
                                                           &stbi_image_free);
    if (!pixels) return bad_map(path, std::string("cannot decode the PNG (") + stbi_failure_reason() + ")");
    NormalMap map;
    map.path = path;
    map.width = width;
    map.height = height;
    const std::size_t count = 3 * static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    map.normals.resize(count);
    for (std::size_t k = 0; k < count; ++k) map.normals[k] = 2.0f * static_cast<float>(pixels.get()[k]) / 255.0f - 1.0f;
    out = std::move(map);
    return Status::success();
  } catch (const std::bad_alloc&) {
    return Status(StatusCode::out_of_memory, path + ": out of memory while loading the normal map");
  }
}

}  // namespace par2d
