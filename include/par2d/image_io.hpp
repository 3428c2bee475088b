// Image files: 8-bit sRGB PNG and float PFM, written all or nothing (temporaries, renamed together at the end).
#pragma once

#include <string>
#include <vector>

#include "par2d/status.hpp"
#include "par2d/types.hpp"

// The public API is what the shared library exports (built with hidden visibility).
#pragma GCC visibility push(default)
namespace par2d {

// Where each output goes. A regular file (or a new one) is written to a hidden temporary in
// its directory and renamed over the target at the end, keeping the target's permission
// bits; a file the user may not write is refused. Devices and FIFOs are written through;
// "-" is standard output (refused when descriptor 1 is closed). Symbolic links are followed to
// their target.

// Writes clamp(exposure * E, 0, 1), sRGB-encoded, as an 8-bit RGB PNG; `dither`: with the
// ordered dither of PixelFormat::rgba8_srgb_dithered (dark gradients do not band).
Status write_png(const std::string& path, const ImageView& image, double exposure = 1.0);
Status write_png(const std::string& path, const ImageView& image, double exposure, bool dither);

// Writes the linear image as a PFM color image: "PF", scale -1.0 (little-endian),
// float32 RGB, bottom row first.
Status write_pfm(const std::string& path, const ImageView& image);

// One file of a write_images batch.
struct ImageOutput {
  enum class Format { png, pfm };
  std::string path;
  Format format = Format::png;
  double exposure = 1.0;  // PNG only
  // The image this file shows; nullptr: the image given to write_images. One batch can so
  // write several images (the shaded and the plain irradiance) all or nothing.
  const ImageView* image = nullptr;
  bool dither = false;  // PNG only: the ordered dither (write_png)
};

// Writes every output or, on any failure, none: all regular files go to temporaries first and
// are renamed into place only once every one is complete, so a failed batch leaves every
// pre-existing file as it was (devices, FIFOs and stdout, which cannot be undone, are
// written after the temporaries are complete). Two outputs naming one file (by identity:
// "./a.png" and "a.png", or a link and its target) are refused before anything is written.
Status write_images(const std::vector<ImageOutput>& outputs, const ImageView& image);

// Deletes the temporaries of writes in progress in this process. Async-signal-safe: call it
// from a SIGINT/SIGTERM handler, then re-raise the signal, and an interrupted write leaves no
// file behind.
void remove_pending_outputs() noexcept;

// Reads a PFM color image written by write_pfm (or any "PF" file of either byte order).
// `pixels` receives width * height * 3 floats, top row first.
Status read_pfm(const std::string& path, int& width, int& height, std::vector<float>& pixels);

}  // namespace par2d
#pragma GCC visibility pop
