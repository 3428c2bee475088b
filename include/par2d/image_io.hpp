// Image files: 8-bit sRGB PNG and float PFM, each written atomically (temporary name, then rename).
#pragma once

#include <string>
#include <vector>

#include "par2d/render.hpp"
#include "par2d/status.hpp"

// The public API is what the shared library exports (built with hidden visibility).
#pragma GCC visibility push(default)
namespace par2d {

// Writes clamp(exposure * E, 0, 1), sRGB-encoded, as an 8-bit RGB PNG.
Status write_png(const std::string& path, const ImageView& image, double exposure = 1.0);

// Writes the linear image as a PFM color image: "PF", scale -1.0 (little-endian),
// float32 RGB, bottom row first.
Status write_pfm(const std::string& path, const ImageView& image);

// Reads a PFM color image written by write_pfm (or any "PF" file of either byte order).
// `pixels` receives width * height * 3 floats, top row first.
Status read_pfm(const std::string& path, int& width, int& height, std::vector<float>& pixels);

}  // namespace par2d
#pragma GCC visibility pop
