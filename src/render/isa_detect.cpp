// Portable half of ISA selection: names, PAR2D_ISA, and which levels a CPU supports. The CPU
// probe itself (detect_isa) lives in isa_detect_<arch>.cpp, one per architecture.
#include <atomic>
#include <cstddef>
#include <cstdlib>

#include "par2d/isa.hpp"
#include "render/isa_usage.hpp"

namespace par2d {
namespace {

// The architecture a level belongs to. Within one architecture the levels nest, each a
// superset of the ones before it in the enum.
enum class IsaFamily { any, x86, arm };

// The one table of ISA facts, a row per Isa in the enum's order. The CPU probe is per
// architecture (isa_detect_<arch>.cpp); the kernels per ISA (render/kernel_table_<arch>.cpp).
struct IsaFacts {
  Isa isa;
  const char* name;         // isa_name, and what parse_isa and PAR2D_ISA accept
  const char* aliases[2];   // other names parse_isa accepts (null: none)
  IsaFamily family;
  int lanes;                // float lanes of its vectors (isa_lanes)
};
constexpr IsaFacts kIsas[] = {
    {Isa::scalar, "scalar", {nullptr, nullptr}, IsaFamily::any, 1},
    {Isa::sse4_2, "sse4", {"sse4.2", "sse4_2"}, IsaFamily::x86, 4},
    {Isa::avx2, "avx2", {nullptr, nullptr}, IsaFamily::x86, 8},
    {Isa::avx512, "avx512", {nullptr, nullptr}, IsaFamily::x86, 16},
    {Isa::neon64, "neon64", {"neon", nullptr}, IsaFamily::arm, 4},
};
constexpr std::size_t kIsaCount = sizeof(kIsas) / sizeof(kIsas[0]);

constexpr bool rows_in_enum_order() noexcept {
  for (std::size_t i = 0; i < kIsaCount; ++i)
    if (static_cast<std::size_t>(kIsas[i].isa) != i) return false;
  return true;
}
static_assert(rows_in_enum_order(), "kIsas lists the levels in Isa's order");

// The row of `isa`, or null for a value outside the enum.
const IsaFacts* isa_facts(Isa isa) noexcept {
  const auto index = static_cast<std::size_t>(isa);
  return index < kIsaCount ? &kIsas[index] : nullptr;
}

std::atomic<std::uint64_t> default_isa_query_count{0};

IsaFamily isa_family(Isa isa) noexcept {
  const IsaFacts* facts = isa_facts(isa);
  return facts ? facts->family : IsaFamily::any;
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
  const IsaFacts* facts = isa_facts(isa);
  return facts ? facts->name : "unknown";
}

std::optional<Isa> parse_isa(std::string_view name) noexcept {
  for (const IsaFacts& facts : kIsas) {
    if (name == facts.name) return facts.isa;
    for (const char* alias : facts.aliases)
      if (alias && name == alias) return facts.isa;
  }
  return std::nullopt;
}

namespace detail {
std::uint64_t default_isa_queries() noexcept { return default_isa_query_count.load(std::memory_order_relaxed); }
}  // namespace detail

int isa_lanes(Isa isa) noexcept {
  const IsaFacts* facts = isa_facts(isa);
  return facts ? facts->lanes : 1;
}

}  // namespace par2d
