// Portable half of ISA selection: names, PAR2D_ISA, and which levels a CPU supports. The CPU
// probe itself (detect_isa) lives in isa_detect_<arch>.cpp, one per architecture.
#include <atomic>
#include <cstdlib>

#include "par2d/isa.hpp"
#include "render/isa_usage.hpp"

namespace par2d {
namespace {

// The architecture a level belongs to. Within one architecture the levels nest, each a
// superset of the ones before it in the enum.
enum class IsaFamily { any, x86, arm };

std::atomic<std::uint64_t> default_isa_query_count{0};

IsaFamily isa_family(Isa isa) noexcept {
  switch (isa) {
    case Isa::scalar: return IsaFamily::any;
    case Isa::sse4_2:
    case Isa::avx2:
    case Isa::avx512: return IsaFamily::x86;
    case Isa::neon64: return IsaFamily::arm;
  }
  return IsaFamily::any;
}

}  // namespace

bool isa_supported(Isa isa) noexcept {
  if (isa == Isa::scalar) return true;
  const Isa best = detect_isa();
  return isa_family(isa) == isa_family(best) && static_cast<int>(isa) <= static_cast<int>(best);
}

Isa capped_isa(Isa wanted) noexcept { return isa_supported(wanted) ? wanted : detect_isa(); }

Isa default_isa() noexcept {
  default_isa_query_count.fetch_add(1, std::memory_order_relaxed);
  if (const char* env = std::getenv("PAR2D_ISA")) {
    if (auto forced = parse_isa(env)) return capped_isa(*forced);
  }
  return detect_isa();
}

const char* isa_name(Isa isa) noexcept {
  switch (isa) {
    case Isa::scalar: return "scalar";
    case Isa::sse4_2: return "sse4";
    case Isa::avx2: return "avx2";
    case Isa::avx512: return "avx512";
    case Isa::neon64: return "neon64";
  }
  return "unknown";
}

std::optional<Isa> parse_isa(std::string_view name) noexcept {
  if (name == "scalar") return Isa::scalar;
  if (name == "sse4" || name == "sse4.2" || name == "sse4_2") return Isa::sse4_2;
  if (name == "avx2") return Isa::avx2;
  if (name == "avx512") return Isa::avx512;
  if (name == "neon64" || name == "neon") return Isa::neon64;
  return std::nullopt;
}

namespace detail {
std::uint64_t default_isa_queries() noexcept { return default_isa_query_count.load(std::memory_order_relaxed); }
}  // namespace detail

int isa_lanes(Isa isa) noexcept {
  switch (isa) {
    case Isa::scalar: return 1;
    case Isa::sse4_2: return 4;
    case Isa::avx2: return 8;
    case Isa::avx512: return 16;
    case Isa::neon64: return 4;
  }
  return 1;
}

}  // namespace par2d
