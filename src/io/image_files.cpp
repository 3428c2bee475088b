// Image files: 8-bit sRGB PNG (stb_image_write) and float PFM, written all or nothing; PFM reading.
#include <fcntl.h>
#include <limits.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <stb/stb_image_write.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "io/file_compat.hpp"
#include "io/output_file.hpp"
#include "io/pixel_encoding.hpp"
#include "par2d/image_io.hpp"

namespace par2d {
namespace {

std::string errno_message(const std::string& path, const char* what, int err) {
  return path + ": " + what + ": " + std::strerror(err);
}

Status check_view(const ImageView& image, const std::string& path) {
  if (image.data == nullptr) return {StatusCode::invalid_argument, path + ": image has no data"};
  if (image.width <= 0 || image.height <= 0)
    return {StatusCode::invalid_argument, path + ": image size " + std::to_string(image.width) +
                                              "x" + std::to_string(image.height) +
                                              " is not positive"};
  if (image.row_stride < 3 * static_cast<std::ptrdiff_t>(image.width))
    return {StatusCode::invalid_argument,
            path + ": row stride " + std::to_string(image.row_stride) +
                " is less than 3 * width (" + std::to_string(3LL * image.width) + ")"};
  return {};
}

bool host_is_little_endian() {
  const std::uint32_t one = 1;
  unsigned char first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

std::uint32_t byte_swap(std::uint32_t v) {
  return (v >> 24) | ((v >> 8) & 0xff00u) | ((v << 8) & 0xff0000u) | (v << 24);
}

void append_bytes(void* context, void* data, int size) {
  auto* out = static_cast<std::pair<std::vector<unsigned char>, bool>*>(context);
  if (out->second || size <= 0) return;
  // stb is C: an exception must not unwind through it, so remember the failure instead.
  try {
    const auto* bytes = static_cast<const unsigned char*>(data);
    out->first.insert(out->first.end(), bytes, bytes + size);
  } catch (const std::bad_alloc&) {
    out->second = true;
  }
}

}  // namespace

namespace {

// The PNG file's bytes for clamp(exposure * E, 0, 1), rounded or with the ordered dither of
// the 8-bit dithered pixel formats (the same codes as a frame rendered in them).
Status encode_png(const std::string& path, const ImageView& image, double exposure, bool dither,
                  std::vector<unsigned char>& png) {
  std::pair<std::vector<unsigned char>, bool> encoded{{}, false};
  try {
    std::vector<unsigned char> rgb(static_cast<std::size_t>(image.width) * image.height * 3);
    for (int j = 0; j < image.height; ++j) {
      const float* row = image.data + j * image.row_stride;
      unsigned char* out = rgb.data() + static_cast<std::size_t>(j) * image.width * 3;
      for (int c = 0; c < 3 * image.width; ++c) {
        const double v = exposure * static_cast<double>(row[c]);
        out[c] = dither ? detail::encode_srgb8_dithered(v, detail::bayer8(c / 3, j)) : detail::encode_srgb8(v);
      }
    }
    int ok = stbi_write_png_to_func(append_bytes, &encoded, image.width, image.height, 3,
                                    rgb.data(), image.width * 3);
    if (!ok || encoded.second)
      return {StatusCode::out_of_memory, path + ": out of memory while encoding PNG"};
  } catch (const std::bad_alloc&) {
    return {StatusCode::out_of_memory, path + ": out of memory while encoding PNG"};
  }
  png = std::move(encoded.first);
  return {};
}

// Streams the PFM rows (bottom row first) into the file.
Status write_pfm_rows(detail::OutputFile& file, const ImageView& image) {
  // Values are stored as they are: PFM is the exact linear output that tests and
  // image_diff compare, so it must not be cleaned up.
  const bool swap = !host_is_little_endian();
  std::vector<float> row;
  try {
    row.resize(static_cast<std::size_t>(image.width) * 3);
  } catch (const std::bad_alloc&) {
    return {StatusCode::out_of_memory, file.path() + ": out of memory"};
  }
  const std::string header =
      "PF\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n-1.0\n";
  if (Status s = file.write(header.data(), header.size()); !s) return s;
  for (int j = image.height - 1; j >= 0; --j) {
    const float* src = image.data + j * image.row_stride;
    std::copy(src, src + row.size(), row.begin());
    if (swap) {
      for (float& v : row) {
        std::uint32_t bits;
        std::memcpy(&bits, &v, 4);
        bits = byte_swap(bits);
        std::memcpy(&v, &bits, 4);
      }
    }
    if (Status s = file.write(row.data(), row.size() * sizeof(float)); !s) return s;
  }
  return {};
}

bool same_target(const detail::OutputFile& a, const detail::OutputFile& b) {
  if (a.path() == "-" || b.path() == "-") return a.path() == b.path();
  if (a.inode() != 0 && a.inode() == b.inode() && a.device() == b.device()) return true;
  std::string ra, rb;
  // Neither exists yet: the same directory (by identity) and the same name.
  const std::size_t sa = a.target().rfind('/'), sb = b.target().rfind('/');
  const std::string da = sa == std::string::npos ? "." : a.target().substr(0, sa + 1);
  const std::string db = sb == std::string::npos ? "." : b.target().substr(0, sb + 1);
  const std::string na = sa == std::string::npos ? a.target() : a.target().substr(sa + 1);
  const std::string nb = sb == std::string::npos ? b.target() : b.target().substr(sb + 1);
  if (na != nb || !detail::canonical_path(da, ra) || !detail::canonical_path(db, rb)) return false;
  return ra == rb;
}

}  // namespace

Status write_images(const std::vector<ImageOutput>& outputs, const ImageView& shared_image) {
  try {
    // Each output's own image, or the shared one.
    auto image_of = [&](const ImageOutput& out) -> const ImageView& { return out.image ? *out.image : shared_image; };
    for (const ImageOutput& out : outputs) {
      const ImageView& image = image_of(out);
      if (Status s = check_view(image, out.path); !s) return s;
      if (out.format == ImageOutput::Format::png) {
        if (!std::isfinite(out.exposure) || out.exposure < 0.0)
          return {StatusCode::invalid_argument, out.path + ": exposure must be finite and >= 0"};
        // stb_image_write sizes its buffers with int arithmetic: (3 * width + 1) * height.
        if ((3LL * image.width + 1) * image.height > INT_MAX / 2)
          return {StatusCode::invalid_argument, out.path + ": image too large for PNG"};
      }
      // Checked before any file is opened: a temporary opened first could take descriptor 1.
      if (out.path == "-" && detail::stdout_closed())
        return {StatusCode::io_error, "-: cannot write: standard output is closed"};
    }
    std::vector<std::unique_ptr<detail::OutputFile>> files;
    for (const ImageOutput& out : outputs) {
      files.push_back(std::make_unique<detail::OutputFile>());
      if (Status s = files.back()->open(out.path); !s) return s;
      for (std::size_t k = 0; k + 1 < files.size(); ++k) {
        if (same_target(*files[k], *files.back()))
          return {StatusCode::invalid_argument, outputs[k].path + " and " + out.path + " are the same file"};
      }
    }
    // Temporaries first, then what writes through (it cannot be taken back), then renames.
    for (bool through : {false, true}) {
      for (std::size_t k = 0; k < outputs.size(); ++k) {
        if (files[k]->writes_through() != through) continue;
        if (outputs[k].format == ImageOutput::Format::pfm) {
          if (Status s = write_pfm_rows(*files[k], image_of(outputs[k])); !s) return s;
          continue;
        }
        std::vector<unsigned char> png;
        if (Status s = encode_png(outputs[k].path, image_of(outputs[k]), outputs[k].exposure, outputs[k].dither, png); !s)
          return s;
        if (Status s = files[k]->write(png.data(), png.size()); !s) return s;
      }
    }
    for (auto& file : files)
      if (Status s = file->commit(); !s) return s;
    return {};
  } catch (const std::bad_alloc&) {
    return {StatusCode::out_of_memory, "writing images: out of memory"};
  }
}

Status write_png(const std::string& path, const ImageView& image, double exposure) {
  return write_images({ImageOutput{path, ImageOutput::Format::png, exposure}}, image);
}

Status write_png(const std::string& path, const ImageView& image, double exposure, bool dither) {
  ImageOutput output{path, ImageOutput::Format::png, exposure};
  output.dither = dither;
  return write_images({output}, image);
}

Status write_pfm(const std::string& path, const ImageView& image) {
  return write_images({ImageOutput{path, ImageOutput::Format::pfm, 1.0}}, image);
}

Status read_pfm(const std::string& path, int& width, int& height, std::vector<float>& pixels) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) return {StatusCode::io_error, errno_message(path, "cannot open", errno)};
  struct Closer {
    std::FILE* f;
    ~Closer() { std::fclose(f); }
  } closer{f};

  // Header: "PF", width, height, scale as whitespace-separated tokens, then exactly one
  // whitespace byte before the raster.
  std::string tokens[4];
  for (int t = 0; t < 4; ++t) {
    int ch = std::fgetc(f);
    while (ch != EOF && std::isspace(ch)) ch = std::fgetc(f);
    while (ch != EOF && !std::isspace(ch) && tokens[t].size() < 64) {
      tokens[t].push_back(static_cast<char>(ch));
      ch = std::fgetc(f);
    }
    if (ch == EOF || tokens[t].empty() || tokens[t].size() >= 64)
      return {StatusCode::io_error, path + ": not a PFM file (truncated or malformed header)"};
  }
  if (tokens[0] == "Pf") return {StatusCode::io_error, path + ": grayscale PFM is not supported"};
  if (tokens[0] != "PF") return {StatusCode::io_error, path + ": not a PFM file (no PF magic)"};

  auto parse_size = [](const std::string& s, int& out) {
    if (s.empty() || s.size() > 9) return false;
    for (char c : s)
      if (c < '0' || c > '9') return false;
    out = std::stoi(s);
    return out > 0;
  };
  int w = 0, h = 0;
  if (!parse_size(tokens[1], w) || !parse_size(tokens[2], h))
    return {StatusCode::io_error, path + ": bad PFM size '" + tokens[1] + " " + tokens[2] + "'"};
  char* end = nullptr;
  double scale = std::strtod(tokens[3].c_str(), &end);
  if (end == tokens[3].c_str() || *end != '\0' || !std::isfinite(scale) || scale == 0.0)
    return {StatusCode::io_error, path + ": bad PFM scale '" + tokens[3] + "'"};
  const bool file_little = scale < 0.0;

  // Check the raster length before allocating, so a corrupt header cannot ask for gigabytes.
  const long raster_start = std::ftell(f);
  struct stat st {};
  if (raster_start < 0 || ::fstat(::fileno(f), &st) != 0)
    return {StatusCode::io_error, errno_message(path, "cannot read", errno)};
  const unsigned long long count = 3ULL * static_cast<unsigned long long>(w) * h;
  if (static_cast<unsigned long long>(st.st_size - raster_start) < count * 4)
    return {StatusCode::io_error, path + ": PFM raster is truncated"};

  std::vector<float> data;
  try {
    data.resize(static_cast<std::size_t>(count));
  } catch (const std::bad_alloc&) {
    return {StatusCode::out_of_memory, path + ": out of memory"};
  }
  const std::size_t row_floats = static_cast<std::size_t>(w) * 3;
  const bool swap = file_little != host_is_little_endian();
  // The file holds the bottom row first; the API returns the top row first.
  for (int j = h - 1; j >= 0; --j) {
    float* dst = data.data() + static_cast<std::size_t>(j) * row_floats;
    if (std::fread(dst, sizeof(float), row_floats, f) != row_floats)
      return {StatusCode::io_error, path + ": PFM raster is truncated"};
    if (swap) {
      for (std::size_t i = 0; i < row_floats; ++i) {
        std::uint32_t bits;
        std::memcpy(&bits, dst + i, 4);
        bits = byte_swap(bits);
        std::memcpy(dst + i, &bits, 4);
      }
    }
  }
  width = w;
  height = h;
  pixels = std::move(data);
  return {};
}

}  // namespace par2d
