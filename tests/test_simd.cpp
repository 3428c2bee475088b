// The SIMD path against the scalar reference (docs/contract.md section 5), for every ISA this CPU
// runs, each forced in turn through the public entry point; kernel-level checks of the
// vector interval merge and atan2; thread-count independence.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "par2d/render.hpp"
#include "render/kernel_table.hpp"
#include "render/kernel_test_hooks.hpp"
#include "world/world.hpp"
#include "scattered_scene.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"
#include "support/test_tiers.hpp"

using namespace par2d;
using namespace par2d::test;

namespace {

RenderOptions simd_options(Isa isa) {
  RenderOptions o;
  o.backend = Backend::simd;
  o.isa = isa;
  return o;
}

RenderOptions scalar_options() {
  RenderOptions o;
  o.backend = Backend::scalar;
  return o;
}

// Compares two renders at the pixels whose centers are farther than 0.05 pixel widths
// from every shape boundary.
Comparison compare(const Scene& scene, const RenderedImage& ref, const RenderedImage& got, double bound) {
  return compare_renders(scene, ref, got, bound, 0.05 * pixel_width(scene));
}

void check_simd_matches_scalar(const Scene& scene, const std::string& what) {
  Status status;
  const RenderedImage ref = render_image(scene, scalar_options(), status);
  REQUIRE_MESSAGE(status.ok(), status.message());
  const double bound = 1e-4 * emission_max_sum(scene);
  for (Isa isa : simd_isas_here()) {
    const RenderedImage got = render_image(scene, simd_options(isa), status);
    REQUIRE_MESSAGE(status.ok(), status.message());
    const Comparison c = compare(scene, ref, got, bound);
    INFO(what, " isa=", std::string(isa_name(isa)), " checked=", c.checked, " max_error=", c.max_error, " bound=", bound);
    CHECK_MESSAGE(c.over == 0, c.first_failure);
  }
}

// Culled SIMD rendering against the scalar reference and, with `against_unculled`, against
// unculled SIMD rendering, for every ISA, within docs/contract.md section 5's bound.
void check_culling_exact(const Scene& scene, bool against_unculled, const std::string& what) {
  Status status;
  const RenderedImage ref = render_image(scene, scalar_options(), status);
  REQUIRE_MESSAGE(status.ok(), status.message());
  const double bound = 1e-4 * emission_max_sum(scene);
  for (Isa isa : simd_isas_here()) {
    RenderOptions culled = simd_options(isa), unculled = simd_options(isa);
    unculled.culling = false;
    const RenderedImage a = render_image(scene, culled, status);
    REQUIRE_MESSAGE(status.ok(), status.message());
    INFO(what, " isa ", std::string(isa_name(isa)));
    const Comparison vs_scalar = compare(scene, ref, a, bound);
    CHECK_MESSAGE(vs_scalar.over == 0, vs_scalar.first_failure);
    CHECK(vs_scalar.checked > scene.width * scene.height / 2);
    if (against_unculled) {
      const RenderedImage b = render_image(scene, unculled, status);
      REQUIRE_MESSAGE(status.ok(), status.message());
      const Comparison vs_unculled = compare(scene, b, a, bound);
      CHECK_MESSAGE(vs_unculled.over == 0, vs_unculled.first_failure);
    }
  }
}

}  // namespace

TEST_CASE("the test runs every SIMD ISA this CPU supports") {
  const std::vector<Isa> isas = simd_isas_here();
  std::string names;
  for (Isa isa : isas) names += std::string(isa_name(isa)) + " ";
  MESSAGE("SIMD ISAs under test: ", names);
  // Every x86-64 CPU this project targets has at least SSE4.2; NEON is baseline on aarch64.
  CHECK(!isas.empty());
  CHECK(isas.back() == detect_isa());
}

TEST_CASE("SIMD matches scalar within 1e-4 e_max on 120 random scenes") {
  for (std::uint32_t seed = 1; seed <= 120; ++seed) {
    RandomSceneOptions opt;
    opt.width = 40 + static_cast<int>(seed % 7) * 9;
    opt.height = 30 + static_cast<int>(seed % 5) * 7;
    opt.max_lights = 4;
    opt.max_occluders = seed % 4 == 0 ? 40 : 14;
    opt.occluders_may_overlap = true;
    if (seed % 6 == 1) opt.view = View{1e5, 1e5, 1e5 + opt.width, 1e5 + opt.height};
    if (seed % 6 == 2) opt.view = View{static_cast<double>(opt.width), 0.0, 0.0, static_cast<double>(opt.height)};
    if (seed % 6 == 3) opt.view = View{-3.0, -2.0, 5.0, 4.0};  // world units much larger than pixels
    if (seed % 6 == 4) opt.outside = 2.0;                        // lights and occluders far outside
    if (seed % 10 == 5) opt.max_polygon_vertices = 40;
    // Pixels of 1e-200 and 1e250 world units: float would underflow or overflow without
    // the kernel's per-tile power-of-two scaling.
    if (seed % 20 == 7) opt.view = View{0.0, 0.0, 1e-200 * opt.width, 1e-200 * opt.height};
    if (seed % 20 == 17) opt.view = View{-1e252, 3e251, -1e252 + 1e250 * opt.width, 3e251 + 1e250 * opt.height};
    const Scene scene = random_scene(seed, opt);
    check_simd_matches_scalar(scene, "seed " + std::to_string(seed));
  }
}

TEST_CASE("SIMD matches scalar at odd image sizes: 1x1, 1023x7, 7x33") {
  const int sizes[][2] = {{1, 1}, {1023, 7}, {7, 33}, {17, 1}};
  std::uint32_t seed = 500;
  for (const auto& size : sizes) {
    RandomSceneOptions opt;
    opt.width = size[0];
    opt.height = size[1];
    opt.view = View{0.0, 0.0, 64.0, 48.0};
    opt.max_occluders = 20;
    check_simd_matches_scalar(random_scene(seed++, opt),
                              "size " + std::to_string(size[0]) + "x" + std::to_string(size[1]));
  }
}

TEST_CASE("SIMD keeps float precision across a 16384-pixel-wide image") {
  // World units are pixels, so shapes near the right edge sit 16384 units from the
  // origin; only tile-relative coordinates keep float exact enough there.
  RandomSceneOptions opt;
  opt.width = 16384;
  opt.height = 2;
  opt.view = View{0.0, 0.0, 16384.0, 2.0};
  opt.min_size = 0.2;
  opt.max_size = 0.9;
  for (std::uint32_t seed = 900; seed < 903; ++seed) {
    Scene scene = random_scene(seed, opt);
    // Move every shape near x = 16000 by shifting the view back over them.
    check_simd_matches_scalar(scene, "wide strip seed " + std::to_string(seed));
  }
}

TEST_CASE("SIMD matches scalar for a view 1e5 units from the origin with many occluders") {
  RandomSceneOptions opt;
  opt.width = 96;
  opt.height = 64;
  opt.view = View{1e5, -1e5, 1e5 + 96, -1e5 + 64};
  opt.min_occluders = 60;
  opt.max_occluders = 80;
  opt.min_size = 0.01;
  opt.max_size = 0.06;
  check_simd_matches_scalar(random_scene(77, opt), "far view, many occluders");
}

TEST_CASE("culling never changes the SIMD image beyond docs/contract.md bounds") {
  for (std::uint32_t seed = 300; seed < 330; ++seed) {
    RandomSceneOptions opt;
    opt.width = 80;
    opt.height = 64;
    opt.max_occluders = 60;
    opt.min_size = 0.01;
    opt.max_size = seed % 3 == 0 ? 0.5 : 0.1;
    const Scene scene = random_scene(seed, opt);
    for (Isa isa : simd_isas_here()) {
      RenderOptions culled = simd_options(isa), unculled = simd_options(isa);
      unculled.culling = false;
      Status status;
      const RenderedImage a = render_image(scene, culled, status);
      REQUIRE(status.ok());
      const RenderedImage b = render_image(scene, unculled, status);
      REQUIRE(status.ok());
      const Comparison c = compare(scene, a, b, 1e-4 * emission_max_sum(scene));
      INFO("seed ", seed, " isa ", std::string(isa_name(isa)));
      CHECK_MESSAGE(c.over == 0, c.first_failure);
    }
  }
}

TEST_CASE("1 thread and N threads give identical bytes") {
  RandomSceneOptions opt;
  opt.width = 131;
  opt.height = 77;
  opt.max_occluders = 30;
  const Scene scene = random_scene(4242, opt);
  std::vector<RenderOptions> variants = {scalar_options()};
  for (Isa isa : simd_isas_here()) variants.push_back(simd_options(isa));
  for (RenderOptions o : variants) {
    o.spp = 4;
    Status status;
    o.threads = 1;
    const RenderedImage one = render_image(scene, o, status);
    REQUIRE(status.ok());
    for (int threads : {2, 3, 8}) {
      o.threads = threads;
      const RenderedImage many = render_image(scene, o, status);
      REQUIRE(status.ok());
      INFO("backend ", std::string(backend_name(o.backend)), " isa ", std::string(o.isa ? isa_name(*o.isa) : "-"), " threads ", threads);
      CHECK(std::memcmp(one.pixels.data(), many.pixels.data(), one.pixels.size() * sizeof(float)) == 0);
    }
  }
}

TEST_CASE("SIMD interval merge equals a plain scalar merge of the same float inputs, exactly") {
  PortableRandom rng(99);
  for (Isa isa : simd_isas_here()) {
    const detail::KernelTestHooks* k = detail::kernel_test_hooks_for(isa);
    REQUIRE(k != nullptr);
    const std::size_t lanes = static_cast<std::size_t>(k->lanes);
    for (int trial = 0; trial < 400; ++trial) {
      const std::size_t count = static_cast<std::size_t>(rng.integer(0, 37));
      std::size_t slots = 1;
      while (slots < count) slots *= 2;
      std::vector<float> lo(slots * lanes + 16), hi(slots * lanes + 16), width(lanes), reach0(lanes), out(lanes);
      // The kernel expects 64-byte aligned rows; align inside the buffers.
      float* lo_a = lo.data() + ((64 - reinterpret_cast<std::uintptr_t>(lo.data()) % 64) % 64) / sizeof(float);
      float* hi_a = hi.data() + ((64 - reinterpret_cast<std::uintptr_t>(hi.data()) % 64) % 64) / sizeof(float);
      std::vector<std::vector<std::pair<float, float>>> per_lane(lanes);
      for (std::size_t l = 0; l < lanes; ++l) {
        width[l] = static_cast<float>(rng.uniform(0.0, 3.2));
        reach0[l] = rng.chance(0.3) ? static_cast<float>(rng.uniform(0.0, width[l])) : 0.0f;
        for (std::size_t i = 0; i < count; ++i) {
          float a = static_cast<float>(rng.uniform(0.0, width[l]));
          float b = rng.chance(0.2) ? a : static_cast<float>(rng.uniform(a, width[l]));
          if (rng.chance(0.1)) a = b = width[l];  // an empty interval, as the kernel makes them
          lo_a[i * lanes + l] = a;
          hi_a[i * lanes + l] = b;
          per_lane[l].push_back({a, b});
        }
      }
      k->union_measure(lo_a, hi_a, count, width.data(), reach0.data(), out.data());
      for (std::size_t l = 0; l < lanes; ++l) {
        auto& v = per_lane[l];
        std::stable_sort(v.begin(), v.end(), [](auto x, auto y) { return x.first < y.first; });
        float covered = reach0[l], reach = reach0[l];
        for (auto [a, b] : v) {
          covered += std::max(b - std::max(a, reach), 0.0f);
          reach = std::max(reach, b);
        }
        INFO("isa ", std::string(isa_name(isa)), " trial ", trial, " lane ", l, " count ", count);
        CHECK(out[l] == covered);
      }
    }
  }
}

TEST_CASE("vector atan2 is within 3e-7 rad of std::atan2 and never NaN, in each form the kernel uses") {
  // Domain 0: any (y, x); 1: y >= 0 (the angle between two directions, from |cross| and dot);
  // 2: x, y >= 0 (a circle's half-width from its radius and tangent length).
  for (int domain = 0; domain < 3; ++domain) {
    PortableRandom rng(7);
    for (Isa isa : simd_isas_here()) {
      const detail::KernelTestHooks* k = detail::kernel_test_hooks_for(isa);
      REQUIRE(k != nullptr);
      const std::size_t lanes = static_cast<std::size_t>(k->lanes);
      double worst = 0.0;
      std::vector<float> y(lanes), x(lanes), out(lanes);
      for (int trial = 0; trial < 20000; ++trial) {
        for (std::size_t l = 0; l < lanes; ++l) {
          const double scale = std::pow(10.0, rng.uniform(-6.0, 6.0));
          y[l] = static_cast<float>(rng.uniform(domain >= 1 ? 0.0 : -1.0, 1.0) * scale);
          x[l] = static_cast<float>(rng.uniform(domain == 2 ? 0.0 : -1.0, 1.0) * scale);
          if (trial == 0 && l == 0) y[l] = x[l] = 0.0f;
          if (trial == 0 && l == 1) y[l] = 0.0f, x[l] = domain == 2 ? 1.0f : -1.0f;
          if (trial == 0 && l == 2) y[l] = 1.0f, x[l] = 0.0f;
        }
        k->atan2(y.data(), x.data(), out.data(), domain);
        for (std::size_t l = 0; l < lanes; ++l) {
          REQUIRE(std::isfinite(out[l]));
          double err = std::abs(static_cast<double>(out[l]) - std::atan2(static_cast<double>(y[l]), static_cast<double>(x[l])));
          err = std::min(err, 2.0 * 3.14159265358979323846 - err);  // +pi and -pi are the same direction
          worst = std::max(worst, err);
        }
      }
      INFO("isa ", std::string(isa_name(isa)), " domain ", domain, " worst error ", worst);
      CHECK(worst < 3e-7);
    }
  }
}

// A probe of the tier check itself (tests/main.cpp), skipped in every normal run: the ctest
// entry test_tiers_catch_an_untagged_case runs it with --no-skip and expects the listener to
// fail the run for it, as it would any new case that renders with the default ISA untagged.
TEST_CASE("tier check probe: resolves the default ISA without the per_isa tag" * doctest::skip()) {
  CHECK(isa_supported(default_isa()));
}

TEST_CASE("PAR2D_ISA caps the default ISA, and the automatic backend follows it" * par2d::test::per_isa()) {
  const char* forced = std::getenv("PAR2D_ISA");
  if (forced == nullptr) {
    CHECK(default_isa() == detect_isa());
    return;
  }
  const std::optional<Isa> wanted = parse_isa(forced);
  REQUIRE_MESSAGE(wanted.has_value(), "PAR2D_ISA=", std::string(forced), " is not an ISA name");
  // A level this CPU has runs as asked; any other (a higher x86 level, or another
  // architecture's) falls back to the best level the CPU has.
  const Isa expected = isa_supported(*wanted) ? *wanted : detect_isa();
  MESSAGE("PAR2D_ISA=", std::string(forced), ": the suite runs the automatic backend at ", std::string(isa_name(expected)));
  CHECK(default_isa() == expected);
  CHECK(resolved_isa(RenderOptions{}) == expected);
}

TEST_CASE("ISA names round-trip, and capped_isa never picks a level this CPU lacks") {
  CHECK(parse_isa("neon") == Isa::neon64);
  CHECK(parse_isa("sse4.2") == Isa::sse4_2);
  CHECK(!parse_isa("sve").has_value());
  CHECK(!parse_isa("").has_value());
  CHECK(isa_supported(Isa::scalar));
  CHECK(capped_isa(Isa::scalar) == Isa::scalar);
  CHECK(capped_isa(detect_isa()) == detect_isa());
  for (Isa isa : kSimdIsas) {
    INFO("isa ", std::string(isa_name(isa)));
    CHECK(parse_isa(isa_name(isa)) == isa);
    const Isa got = capped_isa(isa);
    CHECK(isa_supported(got));
    CHECK((got == isa) == isa_supported(isa));
  }
  // One architecture's levels are never supported on another's CPU, and x86 levels nest.
  const bool x86 = isa_supported(Isa::sse4_2) || isa_supported(Isa::avx2) || isa_supported(Isa::avx512);
  CHECK(!(x86 && isa_supported(Isa::neon64)));
  if (isa_supported(Isa::avx512)) CHECK(isa_supported(Isa::avx2));
  if (isa_supported(Isa::avx2)) CHECK(isa_supported(Isa::sse4_2));
#if defined(__aarch64__)
  CHECK(detect_isa() == Isa::neon64);
  CHECK(capped_isa(Isa::avx2) == Isa::neon64);
#elif defined(__x86_64__)
  CHECK(!isa_supported(Isa::neon64));
  CHECK(capped_isa(Isa::neon64) == detect_isa());
#endif
}

namespace {

struct CullingCase {
  std::uint32_t seed;
  int occluders;
  double min_size, max_size, outside;
};

// Culled against unculled and against the scalar reference, docs/contract.md section 5 bound.
void check_culling_cases(std::initializer_list<CullingCase> cases) {
  for (const CullingCase& c : cases) {
    RandomSceneOptions opt;
    opt.width = 160;
    opt.height = 96;
    opt.min_lights = 3;
    opt.max_lights = 6;
    opt.min_occluders = c.occluders;
    opt.max_occluders = c.occluders;
    opt.min_size = c.min_size;
    opt.max_size = c.max_size;
    opt.outside = c.outside;
    Scene scene = random_scene(c.seed, opt);
    // Long thin occluders across the whole view: segments and slivers, each kept only
    // if it stays disjoint from every light (docs/contract.md section 5's bound needs that).
    PortableRandom rng(c.seed);
    for (int added = 0, tries = 0; added < 12 && tries < 500; ++tries) {
      const Vec2 a{rng.uniform(-40.0, 200.0), rng.uniform(-30.0, 130.0)};
      const Vec2 b{rng.uniform(-40.0, 200.0), rng.uniform(-30.0, 130.0)};
      Occluder thin{Segment{a, b}};
      if (tries % 2 == 1) {
        const Vec2 d{b.x - a.x, b.y - a.y};
        const double len = std::hypot(d.x, d.y);
        const Vec2 n{-d.y / len * 0.3, d.x / len * 0.3};
        thin.shape = Polygon{{a, b, {b.x + n.x, b.y + n.y}, {a.x + n.x, a.y + n.y}}};
      }
      const Scene probe{scene.width, scene.height, scene.view, scene.lights, {thin}};
      const auto prepared = detail::prepare_scene(probe);
      if (std::any_of(prepared.lights.begin(), prepared.lights.end(),
                      [](const detail::PreparedLight& l) { return !l.overlapping_occluders.empty(); }))
        continue;
      scene.occluders.push_back(thin);
      ++added;
    }
    REQUIRE(validate_scene(scene).ok());
    REQUIRE(!scene.lights.empty());
    // Unculled, every pixel merges every occluder for every light: too slow for a unit
    // test at 1000 occluders, so that case is held to the scalar reference only.
    check_culling_exact(scene, scene.occluders.size() <= 500,
                        "seed " + std::to_string(c.seed) + " occluders " + std::to_string(scene.occluders.size()));
  }
}

// The scaling benchmark's kind of level, scaled down: 16 lights among 400 occluders of 4..12
// px over 192 x 128 px, so that light reach, block proofs and tile proofs all decide; lights
// [first, last] of them, one at a time.
void check_dense_field(std::size_t first, std::size_t last) {
  Scene scene = bench::scattered_scene(16, 400, 1, 192, 128);
  const auto prepared = detail::prepare_scene(scene);
  REQUIRE(std::all_of(prepared.lights.begin(), prepared.lights.end(),
                      [](const detail::PreparedLight& l) { return l.overlapping_occluders.empty(); }));
  REQUIRE(scene.lights.size() == 16);
  // One light at a time: the contract's bound scales with the sum of emissions, and alone a light
  // seen through a crack that a wrong proof closed stands out against it.
  const std::vector<Light> lights = scene.lights;
  for (std::size_t l = first; l <= last; ++l) {
    scene.lights = {lights[l]};
    REQUIRE(validate_scene(scene).ok());
    check_culling_exact(scene, true, "light " + std::to_string(l));
  }
}

}  // namespace

TEST_CASE("culling is exact with up to 1000 occluders: long thin ones, ones spanning many tiles, far lights") {
  check_culling_cases({
      {1202, 16, 0.1, 0.35, 0.15},  // large occluders spanning many 16 px tiles
      {1203, 300, 0.01, 0.05, 3.0},  // lights and occluders far outside the image
  });
}

TEST_CASE("culling is exact with 1000 small scattered occluders and long thin ones" * par2d::test::long_tier()) {
  check_culling_cases({{1201, 1000, 0.004, 0.02, 0.15}});
}

TEST_CASE("culling is exact in a dense field where most lights are hidden by many occluders together") {
  check_dense_field(0, 0);
}

TEST_CASE("culling is exact in a dense field, two more lights" * par2d::test::long_tier()) { check_dense_field(1, 2); }

TEST_CASE("a 0.1-unit polygon light 1e7 from the origin keeps its winding: inside it E is the full emission") {
  // The shoelace area over absolute coordinates (~1e14 per term) cancels to noise here; a
  // wrong sign turned the light inside out (fuzz finding).
  Scene scene;
  scene.width = 3;
  scene.height = 3;
  scene.view = View{1e7, 1e7, 1e7 + 0.003, 1e7 + 0.008};
  // The fuzzer's 19-gon (about 0.13 units across), whose absolute shoelace sum has the wrong sign.
  const Polygon light_shape{{{9999999.93062518, 10000000.018454172}, {9999999.916376173, 10000000.002935441}, {9999999.90793814, 9999999.983630914}, {9999999.906225473, 9999999.962632535}, {9999999.911423767, 9999999.942215804}, {9999999.922969703, 9999999.924593192}, {9999999.939612102, 9999999.911674378}, {9999999.959547501, 9999999.904859321}, {9999999.980615592, 9999999.904886536}, {10000000.000533318, 9999999.911753075}, {10000000.017142285, 9999999.924714841}, {10000000.028642654, 9999999.942367224}, {10000000.033788182, 9999999.962797318}, {10000000.032021271, 9999999.983791202}, {10000000.023533393, 10000000.003073866}, {10000000.009244341, 10000000.01855573}, {9999999.990702555, 10000000.028559098}, {9999999.969917327, 10000000.031999948}, {9999999.949141057, 10000000.02850541}}};
  scene.lights.push_back(Light{light_shape, {1.0, 1.0, 1.0}, 2.0});
  std::vector<RenderOptions> variants = {scalar_options()};
  for (Isa isa : simd_isas_here()) variants.push_back(simd_options(isa));
  for (const RenderOptions& o : variants) {
    Status status;
    const RenderedImage got = render_image(scene, o, status);
    REQUIRE(status.ok());
    for (float v : got.pixels) CHECK(v == doctest::Approx(2.0).epsilon(1e-6));
  }
}

TEST_CASE("isa_lanes reports the lane count of each compiled kernel; its test hooks match it") {
  CHECK(isa_lanes(Isa::scalar) == 1);
  CHECK(detail::kernels_for(Isa::scalar) == nullptr);
  CHECK(detail::kernel_test_hooks_for(Isa::scalar) == nullptr);
  std::vector<Isa> compiled;
  for (Isa isa : kSimdIsas) {
    const detail::KernelSet* k = detail::kernels_for(isa);
    const detail::KernelTestHooks* hooks = detail::kernel_test_hooks_for(isa);
    // Every level the CPU supports has a kernel; a level without one is never selected.
    if (isa_supported(isa)) REQUIRE(k != nullptr);
    // The test hooks exist for exactly the kernels compiled, with their lane count.
    CHECK((hooks == nullptr) == (k == nullptr));
    if (k == nullptr) {
      CHECK(capped_isa(isa) != isa);
      continue;
    }
    compiled.push_back(isa);
    CHECK(k->isa == isa);
    CHECK(k->lanes == isa_lanes(isa));
    REQUIRE(hooks != nullptr);
    CHECK(hooks->isa == isa);
    CHECK(hooks->lanes == k->lanes);
  }
  // Exactly the target architecture's kernels are compiled in.
#if defined(__x86_64__) || defined(__i386__)
  CHECK(compiled == std::vector<Isa>{Isa::sse4_2, Isa::avx2, Isa::avx512});
#elif defined(__aarch64__)
  CHECK(compiled == std::vector<Isa>{Isa::neon64});
#else
  CHECK(compiled.empty());
#endif
}
