// Image files: 8-bit sRGB PNG (stb_image_write) and float PFM, written atomically; PFM reading.
#include <fcntl.h>
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
#include <new>
#include <string>
#include <vector>

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

// A file that appears under its final name only when complete: the bytes go to a
// uniquely named sibling (same directory, so rename() is atomic on POSIX), and the
// destructor removes that sibling unless commit() succeeded. Readers therefore see
// either the old file or the whole new one, never a partial write.
class AtomicFile {
 public:
  explicit AtomicFile(std::string path) : path_(std::move(path)) {}
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!temp_.empty()) ::unlink(temp_.c_str());
  }

  Status open() {
    // open(O_EXCL) with 0666 rather than mkstemp: mkstemp creates mode 0600, while the
    // caller's umask should decide the final file's permissions as for any other output.
    static std::atomic<unsigned> counter{0};
    for (int attempt = 0; attempt < 100; ++attempt) {
      std::string name = path_ + ".tmp" + std::to_string(::getpid()) + "." +
                         std::to_string(counter.fetch_add(1, std::memory_order_relaxed));
      int fd = ::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      if (fd >= 0) {
        fd_ = fd;
        temp_ = std::move(name);
        return {};
      }
      if (errno != EEXIST) return {StatusCode::io_error, errno_message(path_, "cannot create", errno)};
    }
    return {StatusCode::io_error, path_ + ": cannot create a unique temporary file next to it"};
  }

  Status write(const void* data, std::size_t size) {
    const char* bytes = static_cast<const char*>(data);
    while (size > 0) {
      // Some kernels cap one write() at about 2 GiB; loop over partial writes.
      ssize_t n = ::write(fd_, bytes, std::min<std::size_t>(size, std::size_t{1} << 30));
      if (n < 0) {
        if (errno == EINTR) continue;
        return {StatusCode::io_error, errno_message(path_, "write failed", errno)};
      }
      bytes += n;
      size -= static_cast<std::size_t>(n);
    }
    return {};
  }

  Status commit() {
    int fd = fd_;
    fd_ = -1;
    // close() reports deferred write errors (NFS, quota), so its result matters.
    if (::close(fd) != 0) return {StatusCode::io_error, errno_message(path_, "write failed", errno)};
    if (::rename(temp_.c_str(), path_.c_str()) != 0)
      return {StatusCode::io_error, errno_message(path_, "cannot write", errno)};
    temp_.clear();
    return {};
  }

 private:
  std::string path_;
  std::string temp_;
  int fd_ = -1;
};

// Linear values at which the rounded 8-bit sRGB code steps from k-1 to k, k = 1..255:
// the exact inverse transfer function at (k - 0.5) / 255. Looking a value up among them
// equals round(255 * srgb(clamp(v, 0, 1))) without a pow() per channel.
const std::array<double, 255>& srgb_thresholds() {
  static const std::array<double, 255> table = [] {
    std::array<double, 255> t{};
    for (int k = 1; k <= 255; ++k) {
      double s = (k - 0.5) / 255.0;
      t[k - 1] = s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
    }
    return t;
  }();
  return table;
}

unsigned char encode_srgb8(double linear, const std::array<double, 255>& thresholds) {
  // NaN compares false everywhere, so it lands on 0 like a negative value.
  if (!(linear > 0.0)) return 0;
  if (linear >= 1.0) return 255;
  auto it = std::upper_bound(thresholds.begin(), thresholds.end(), linear);
  return static_cast<unsigned char>(it - thresholds.begin());
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

Status write_png(const std::string& path, const ImageView& image, double exposure) {
  if (Status s = check_view(image, path); !s) return s;
  if (!std::isfinite(exposure) || exposure < 0.0)
    return {StatusCode::invalid_argument, path + ": exposure must be finite and >= 0"};
  // stb_image_write sizes its buffers with int arithmetic: (3 * width + 1) * height.
  if ((3LL * image.width + 1) * image.height > INT_MAX / 2)
    return {StatusCode::invalid_argument, path + ": image too large for PNG"};

  std::pair<std::vector<unsigned char>, bool> encoded{{}, false};
  try {
    const auto& thresholds = srgb_thresholds();
    std::vector<unsigned char> rgb(static_cast<std::size_t>(image.width) * image.height * 3);
    for (int j = 0; j < image.height; ++j) {
      const float* row = image.data + j * image.row_stride;
      unsigned char* out = rgb.data() + static_cast<std::size_t>(j) * image.width * 3;
      for (int c = 0; c < 3 * image.width; ++c)
        out[c] = encode_srgb8(exposure * static_cast<double>(row[c]), thresholds);
    }
    int ok = stbi_write_png_to_func(append_bytes, &encoded, image.width, image.height, 3,
                                    rgb.data(), image.width * 3);
    if (!ok || encoded.second)
      return {StatusCode::out_of_memory, path + ": out of memory while encoding PNG"};
  } catch (const std::bad_alloc&) {
    return {StatusCode::out_of_memory, path + ": out of memory while encoding PNG"};
  }

  AtomicFile file(path);
  if (Status s = file.open(); !s) return s;
  if (Status s = file.write(encoded.first.data(), encoded.first.size()); !s) return s;
  return file.commit();
}

Status write_pfm(const std::string& path, const ImageView& image) {
  if (Status s = check_view(image, path); !s) return s;
  // Values are stored as they are (NaN and negatives included): PFM is the exact
  // linear output that tests and image_diff compare, so it must not be cleaned up.
  const bool swap = !host_is_little_endian();
  std::vector<float> row;
  try {
    row.resize(static_cast<std::size_t>(image.width) * 3);
  } catch (const std::bad_alloc&) {
    return {StatusCode::out_of_memory, path + ": out of memory"};
  }

  AtomicFile file(path);
  if (Status s = file.open(); !s) return s;
  const std::string header =
      "PF\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n-1.0\n";
  if (Status s = file.write(header.data(), header.size()); !s) return s;
  // PFM stores the bottom row first.
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
  return file.commit();
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
