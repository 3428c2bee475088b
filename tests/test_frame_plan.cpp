// Frame plans (render/frame_plan.hpp): what plan_frame decides per block and per stage, and
// FrameEngine::run executing hand-edited plans, block by block, against whole frames rendered
// through the public API with each backend; blocks dealt to lanes as they finish, and the
// arenas schedulers keep for one another.
#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <utility>
#include <vector>

#include "culling/light_reach.hpp"
#include "culling/reach_cache.hpp"
#include "par2d/isa.hpp"
#include "par2d/render.hpp"
#include "par2d/renderer.hpp"
#include "parallel/scheduler.hpp"
#include "render/frame_driver.hpp"
#include "render/frame_plan.hpp"
#include "render/kernel_table.hpp"
#include "render/light_layers.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"
#include "world/world.hpp"

#if !PAR2D_STD_THREADS
#include <tbb/task_arena.h>
#endif

namespace par2d::test {
namespace {

using detail::BlockStrategy;
using detail::FramePlan;
using detail::PlannedBlock;

// A 200 x 140 frame: 4 x 3 blocks of 64 px, the last column 8 px wide and the last row 12 px
// high. `albedo`: some occluders reflect (a bounce term).
Scene plan_scene(std::uint32_t seed, bool albedo) {
  RandomSceneOptions options;
  options.width = 200;
  options.height = 140;
  options.min_lights = 3;
  options.max_lights = 6;
  options.min_occluders = 8;
  options.max_occluders = 14;
  options.max_size = 0.12;
  options.ambient = true;
  Scene scene = random_scene(seed, options);
  if (albedo) {
    for (std::size_t i = 0; i < scene.occluders.size(); i += 2) scene.occluders[i].albedo = {0.6, 0.5, 0.4};
    scene.bounce.piece = 8.0;
  }
  return scene;
}

// Per light, the reach a Renderer culls with.
std::vector<detail::LightReach> reach_of(const detail::PreparedScene& scene) {
  std::vector<detail::LightReach> reach;
  detail::LightReachScratch scratch;
  for (std::size_t l = 0; l < scene.lights.size(); ++l) reach.push_back(detail::compute_light_reach(scene, l, scratch));
  return reach;
}

// A whole frame of `scene` through the public API, float RGB.
std::vector<float> whole_frame(const Scene& scene, Backend backend, Isa isa, BounceTerm bounce = BounceTerm::included) {
  RenderOptions options;
  options.backend = backend;
  if (backend == Backend::simd) options.isa = isa;
  options.threads = 2;
  options.bounce = bounce;
  std::vector<float> pixels(static_cast<std::size_t>(scene.width) * static_cast<std::size_t>(scene.height) * 3, -1.0f);
  const Status s = render(scene, options, ImageView{pixels.data(), scene.width, scene.height, scene.width * 3});
  REQUIRE_MESSAGE(s.ok(), s.message());
  return pixels;
}

// The SIMD levels compiled here that this CPU runs.
std::vector<Isa> kernel_isas() {
  std::vector<Isa> isas;
  const detail::CompiledKernels compiled = detail::compiled_kernels();
  for (std::size_t k = 0; k < compiled.count; ++k)
    if (isa_supported(compiled.kernels[k].isa)) isas.push_back(compiled.kernels[k].isa);
  return isas;
}

// A float RGB frame `plan` writes its region of, rows `width` pixels apart, every value first
// `canary`.
struct Target {
  std::vector<float> pixels;
  detail::FrameTarget frame;
  Target(const detail::TileRect& region, float canary) {
    const int w = region.x1 - region.x0, h = region.y1 - region.y0;
    pixels.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3, canary);
    frame.data = reinterpret_cast<unsigned char*>(pixels.data());
    frame.format = PixelFormat::rgb_f32;
    frame.row_stride = static_cast<std::ptrdiff_t>(w) * 3 * static_cast<std::ptrdiff_t>(sizeof(float));
    frame.region = region;
  }
};

// The planned block holding pixel (x, y), or null.
const PlannedBlock* block_at(const FramePlan& plan, int x, int y) {
  for (const PlannedBlock& b : plan.blocks)
    if (b.rect.x0 <= x && x < b.rect.x1 && b.rect.y0 <= y && y < b.rect.y1) return &b;
  return nullptr;
}

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Checks every pixel of `target` (its region of a `width`-wide frame): inside a planned block,
// the bits of `expected(block)`'s pixel; elsewhere the canary. Returns the pixels compared
// against a whole frame.
template <class Expected>
std::size_t check_pixels(const FramePlan& plan, const Target& target, int width, float canary, Expected&& expected) {
  const detail::TileRect& r = target.frame.region;
  std::size_t computed = 0, wrong = 0, touched = 0;
  for (int y = r.y0; y < r.y1; ++y) {
    for (int x = r.x0; x < r.x1; ++x) {
      const PlannedBlock* block = block_at(plan, x, y);
      for (int c = 0; c < 3; ++c) {
        const float got = target.pixels[(static_cast<std::size_t>(y - r.y0) * (r.x1 - r.x0) + (x - r.x0)) * 3 + c];
        if (!block) {
          touched += same_bits(got, canary) ? 0u : 1u;
        } else {
          const std::vector<float>& frame = expected(*block);
          wrong += same_bits(got, frame[(static_cast<std::size_t>(y) * width + x) * 3 + c]) ? 0u : 1u;
        }
      }
      computed += block ? 1u : 0u;
    }
  }
  CHECK_MESSAGE(wrong == 0, wrong, " values differ from the whole frame of their block's backend");
  CHECK_MESSAGE(touched == 0, touched, " values outside the planned blocks were written");
  return computed;
}

}  // namespace

TEST_CASE("a plan mixing kernel and scalar_reference blocks gives each block its backend's whole-frame pixels, bit for bit") {
  const std::vector<Isa> isas = kernel_isas();
  if (isas.empty()) {
    MESSAGE("no SIMD kernel for this architecture: every plan is the reference's, nothing to mix");
    return;
  }
  detail::Scheduler scheduler;
  scheduler.configure(2, Threading::own_pool);
  for (const bool albedo : {false, true}) {
    const Scene scene = plan_scene(albedo ? 31u : 17u, albedo);
    const detail::PreparedScene prepared = detail::prepare_scene(scene);
    const std::vector<detail::LightReach> reach = reach_of(prepared);
    const std::vector<float> reference = whole_frame(scene, Backend::scalar, Isa::scalar);
    for (const Isa isa : isas) {
      CAPTURE(isa_name(isa));
      CAPTURE(albedo);
      const std::vector<float> kernel = whole_frame(scene, Backend::simd, isa);
      detail::FrameSettings settings;
      settings.isa = isa;
      const detail::TileRect frame{0, 0, scene.width, scene.height};
      FramePlan plan;
      detail::plan_frame(prepared, settings, frame, &reach, nullptr, nullptr, plan);
      REQUIRE(plan.blocks.size() == 12);
      CHECK(plan.bounce.run == albedo);
      // Blocks alternate in a checkerboard, so every block has neighbours of the other kind.
      for (PlannedBlock& b : plan.blocks) {
        REQUIRE(b.strategy == BlockStrategy::kernel);
        if ((b.rect.x0 / detail::kBlockSize + b.rect.y0 / detail::kBlockSize) % 2 == 0)
          b.strategy = BlockStrategy::scalar_reference;
      }
      Target target(frame, -7.0f);
      detail::FrameEngine engine;
      REQUIRE(engine.run(plan, prepared, scheduler, target.frame));
      const std::size_t computed = check_pixels(plan, target, scene.width, -7.0f, [&](const PlannedBlock& b) -> const std::vector<float>& {
        return b.strategy == BlockStrategy::scalar_reference ? reference : kernel;
      });
      CHECK(computed == static_cast<std::size_t>(scene.width) * static_cast<std::size_t>(scene.height));
      // The two backends differ somewhere (else the test could not tell which ran where).
      CHECK(std::memcmp(reference.data(), kernel.data(), reference.size() * sizeof(float)) != 0);
    }
  }
}

TEST_CASE("a plan over some blocks of a region computes them as a whole frame does and leaves every other pixel untouched") {
  const Scene scene = plan_scene(23u, true);
  const detail::PreparedScene prepared = detail::prepare_scene(scene);
  const std::vector<detail::LightReach> reach = reach_of(prepared);
  detail::Scheduler scheduler;
  scheduler.configure(2, Threading::own_pool);
  std::vector<Isa> isas = kernel_isas();
  isas.push_back(Isa::scalar);
  for (const Isa isa : isas) {
    CAPTURE(isa_name(isa));
    const std::vector<float> whole =
        isa == Isa::scalar ? whole_frame(scene, Backend::scalar, isa) : whole_frame(scene, Backend::simd, isa);
    detail::FrameSettings settings;
    settings.isa = isa;
    settings.culling = isa != Isa::scalar;
    // Blocks 1, 4, 6, 9 and 11 of the frame's 4 x 3, in a region that cuts blocks on every
    // side and leaves block 11 out.
    std::vector<std::uint8_t> dirty(12, 0);
    for (const int b : {1, 4, 6, 9, 11}) dirty[static_cast<std::size_t>(b)] = 1;
    const detail::TileRect region{30, 20, 190, 135};
    FramePlan plan;
    detail::plan_frame(prepared, settings, region, settings.culling ? &reach : nullptr, &dirty, nullptr, plan);
    REQUIRE(plan.blocks.size() == 4);  // block 11 is outside the region
    Target target(region, 1e30f);
    detail::FrameEngine engine;
    REQUIRE(engine.run(plan, prepared, scheduler, target.frame));
    const std::size_t computed =
        check_pixels(plan, target, scene.width, 1e30f, [&](const PlannedBlock&) -> const std::vector<float>& { return whole; });
    // The planned blocks within the region: (64..128) x (20..64), (30..64) x (64..128),
    // (128..190) x (64..128) and (64..128) x (128..135).
    CHECK(computed == 64u * 44u + 34u * 64u + 62u * 64u + 64u * 7u);
    // Nothing planned: nothing written, the progress function told of no tile.
    std::fill(dirty.begin(), dirty.end(), 0);
    detail::plan_frame(prepared, settings, region, settings.culling ? &reach : nullptr, &dirty, nullptr, plan);
    CHECK(plan.blocks.empty());
    CHECK(plan.tiles == 0);
    Target untouched(region, 1e30f);
    int reports = 0;
    const ProgressFunction progress = [&](const Progress& p) {
      ++reports;
      CHECK(p.tiles == 0);
      return true;
    };
    const detail::FrameControl control{&progress, nullptr};
    REQUIRE(engine.run(plan, prepared, scheduler, untouched.frame, nullptr, &control));
    CHECK(reports == 1);
    check_pixels(plan, untouched, scene.width, 1e30f, [&](const PlannedBlock&) -> const std::vector<float>& { return whole; });
  }
}

TEST_CASE("plan_frame: dirty flags pick the blocks in frame order; the scalar ISA and the bounce alone take no layers") {
  const Scene scene = plan_scene(41u, true);
  const detail::PreparedScene prepared = detail::prepare_scene(scene);
  const std::vector<detail::LightReach> reach = reach_of(prepared);
  const std::vector<Isa> isas = kernel_isas();
  const Isa simd = isas.empty() ? Isa::scalar : isas.back();
  detail::LightLayerCache layers;
  layers.set_budget(std::size_t{64} << 20);
  layers.set_block_count(12);
  const detail::TileRect frame{0, 0, scene.width, scene.height};
  FramePlan plan;

  SUBCASE("dirty flags: only the flagged blocks, row by row, each with its rectangle and number") {
    std::vector<std::uint8_t> dirty(12, 0);
    for (const int b : {10, 2, 3, 7}) dirty[static_cast<std::size_t>(b)] = 1;
    detail::FrameSettings settings;
    settings.isa = simd;
    detail::plan_frame(prepared, settings, frame, &reach, &dirty, nullptr, plan);
    REQUIRE(plan.blocks.size() == 4);
    const std::uint32_t expected[] = {2, 3, 7, 10};
    for (std::size_t k = 0; k < 4; ++k) {
      const PlannedBlock& b = plan.blocks[k];
      CHECK(b.index == expected[k]);
      CHECK(b.rect.x0 == static_cast<int>(expected[k] % 4) * 64);
      CHECK(b.rect.y0 == static_cast<int>(expected[k] / 4) * 64);
      // Whole past the frame's edges (200 x 140): the pixels outside are computed and dropped.
      CHECK(b.rect.x1 == b.rect.x0 + 64);
      CHECK(b.rect.y1 == b.rect.y0 + 64);
      CHECK((b.part.x0 == b.rect.x0 && b.part.y0 == b.rect.y0 && b.part.x1 == b.rect.x1 && b.part.y1 == b.rect.y1));
    }
    // Tiles of 16 px meeting the frame: blocks 2 and 10 are 4 x 4 and 4 x 1 tiles, blocks 3
    // and 7 are 1 x 4.
    CHECK(plan.tiles == 16u + 4u + 4u + 4u);
    CHECK(plan.cull_reach == &reach);
  }
  SUBCASE("a view offset: blocks on the pixel grid; a move's uncovered bands compute only their tiles") {
    detail::PreparedScene moved = detail::prepare_scene(scene);
    moved.grid_x = 70;  // block corners at grid multiples of 64: frame columns -6, 58, 122, 186
    moved.grid_y = -3;  // rows 3, 67, 131 (and -61)
    const detail::BlockGrid grid = detail::frame_blocks(moved);
    CHECK(grid.ax == 6);
    CHECK(grid.ay == 61);
    CHECK(grid.columns == 4);  // (200 + 6) / 64, rounded up
    CHECK(grid.rows == 4);     // (140 + 61) / 64, rounded up
    std::vector<std::uint8_t> dirty(grid.count(), detail::kBlockClean);
    dirty[0] = detail::kBlockWhole;
    dirty[3] = detail::kBlockUncovered;   // column 3, row 0: the right band's
    dirty[13] = detail::kBlockUncovered;  // column 1, row 3: the bottom band's
    detail::UncoveredPixels uncovered;
    uncovered.columns = {186, 0, 200, 140};
    uncovered.rows = {0, 131, 200, 140};
    detail::FrameSettings settings;
    settings.isa = simd;
    detail::plan_frame(moved, settings, frame, &reach, &dirty, nullptr, plan, &uncovered);
    REQUIRE(plan.blocks.size() == 3);
    CHECK((plan.blocks[0].rect.x0 == -6 && plan.blocks[0].rect.y0 == -61 && plan.blocks[0].rect.x1 == 58));
    CHECK(plan.blocks[0].part.x1 == 58);
    CHECK((plan.blocks[1].rect.x0 == 186 && plan.blocks[1].rect.y0 == -61));
    CHECK((plan.blocks[1].part.x0 == 186 && plan.blocks[1].part.y0 == 0 && plan.blocks[1].part.y1 == 3));
    CHECK((plan.blocks[2].rect.x0 == 58 && plan.blocks[2].rect.y0 == 131));
    CHECK((plan.blocks[2].part.y0 == 131 && plan.blocks[2].part.y1 == 140 && plan.blocks[2].part.x0 == 58));
    // Block row 0 spans rows -61..3: of its tile rows (-61, -45, -29, -13) only -13..3 meets
    // the frame. Block 0's tiles there: columns -6, 10, 26, 42: 4; the right band's block: its
    // first tile column (186..202): 1; the bottom band's: tile row 131..147 across 4 columns: 4.
    CHECK(plan.tiles == 4u + 1u + 4u);
  }
  SUBCASE("the scalar ISA: every block by the reference, no layers, no culling, no kernels") {
    detail::FrameSettings settings;
    settings.isa = Isa::scalar;
    settings.culling = false;
    detail::plan_frame(prepared, settings, frame, nullptr, nullptr, &layers, plan);
    REQUIRE(plan.blocks.size() == 12);
    for (const PlannedBlock& b : plan.blocks) CHECK(b.strategy == BlockStrategy::scalar_reference);
    CHECK(plan.layers == nullptr);
    CHECK(plan.kernels == nullptr);
    CHECK(plan.cull_reach == nullptr);
    CHECK(plan.bounce.run);
    CHECK_FALSE(plan.bounce.cull);
  }
  SUBCASE("the bounce alone: no direct light in any block, no layers; excluded: no bounce stage") {
    detail::FrameSettings settings;
    settings.isa = simd;
    settings.bounce = BounceTerm::only;
    detail::plan_frame(prepared, settings, frame, &reach, nullptr, &layers, plan);
    REQUIRE(plan.blocks.size() == 12);
    for (const PlannedBlock& b : plan.blocks) CHECK(b.strategy == BlockStrategy::no_direct);
    CHECK(plan.layers == nullptr);
    CHECK(plan.bounce.run);
    CHECK(plan.bounce.cull == (simd != Isa::scalar));
    settings.bounce = BounceTerm::excluded;
    detail::plan_frame(prepared, settings, frame, &reach, nullptr, nullptr, plan);
    CHECK_FALSE(plan.bounce.run);
    for (const PlannedBlock& b : plan.blocks) CHECK(b.strategy == (simd == Isa::scalar ? BlockStrategy::scalar_reference : BlockStrategy::kernel));
  }
}

TEST_CASE("plan_frame with a light-layer cache: blocks fill their layers, then recombine from them alone") {
  const std::vector<Isa> isas = kernel_isas();
  if (isas.empty()) {
    MESSAGE("no SIMD kernel for this architecture: no layers (they hold what a kernel computes)");
    return;
  }
  Scene scene = plan_scene(53u, false);
  const detail::PreparedScene prepared = detail::prepare_scene(scene);
  const std::vector<detail::LightReach> reach = reach_of(prepared);
  detail::Scheduler scheduler;
  scheduler.configure(2, Threading::own_pool);
  detail::FrameSettings settings;
  settings.isa = isas.back();
  const detail::TileRect frame{0, 0, scene.width, scene.height};
  // Every light takes part in every block (the cache's own plan, as the change tracker makes it).
  std::vector<std::uint32_t> first, lights;
  for (std::uint32_t b = 0; b <= 12; ++b) first.push_back(b * static_cast<std::uint32_t>(prepared.lights.size()));
  for (std::uint32_t b = 0; b < 12; ++b)
    for (std::uint32_t l = 0; l < prepared.lights.size(); ++l) lights.push_back(l);
  detail::LightLayerCache layers;
  layers.set_budget(std::size_t{256} << 20);
  layers.set_block_count(12);
  detail::FrameEngine engine;
  const std::vector<float> kernel = whole_frame(scene, Backend::simd, settings.isa);
  for (int frame_number = 0; frame_number < 2; ++frame_number) {
    CAPTURE(frame_number);
    layers.plan_frame(nullptr, first, lights, false, 3);
    FramePlan plan;
    detail::plan_frame(prepared, settings, frame, &reach, nullptr, &layers, plan);
    REQUIRE(plan.blocks.size() == 12);
    CHECK(plan.layers == &layers);
    for (const PlannedBlock& b : plan.blocks) {
      if (frame_number == 0) {  // no layer yet, room for all
        CHECK(b.strategy == BlockStrategy::layered);
        CHECK(b.fill_layers);
      } else {  // every light of every block has its layer
        CHECK(b.strategy == BlockStrategy::recombine);
      }
    }
    Target target(frame, -7.0f);
    REQUIRE(engine.run(plan, prepared, scheduler, target.frame));
    // Layers differ from the kernel by one more rounding per light (docs/api.md's bound).
    double worst = 0.0;
    for (std::size_t i = 0; i < kernel.size(); ++i)
      worst = std::max(worst, std::abs(static_cast<double>(target.pixels[i]) - kernel[i]));
    CHECK(worst <= 1e-6 * emission_max_sum(scene));
  }
}

TEST_CASE("the reach cache across view offsets: kept while the radii tried stay, proven again when they change, as a fresh proof") {
  const Scene scene = plan_scene(61u, false);
  detail::World world;
  detail::ReachCache cache;
  world.observe(&cache);
  REQUIRE(world.set_scene(scene, nullptr, nullptr).ok());
  detail::Scheduler scheduler;
  scheduler.configure(1, Threading::own_pool);
  CHECK(cache.update(world.commit(), scheduler) == world.commit().lights.size());
  std::size_t kept = 0, proven = 0;
  // Pans of a few pixels, then jumps far enough that the farthest view corner moves past
  // several radii of every light.
  for (const auto& offset : std::vector<std::pair<int, int>>{{1, 0}, {2, 1}, {3, 3}, {400, 0}, {400, 300}, {-900, -700}, {-899, -700}}) {
    REQUIRE(world.set_view_offset(offset.first, offset.second).ok());
    const detail::PreparedScene& prepared = world.commit();
    const std::size_t n = cache.update(prepared, scheduler);
    (n == 0 ? kept : proven) += 1;
    detail::LightReachScratch scratch;
    for (std::size_t p = 0; p < prepared.lights.size(); ++p) {
      CAPTURE(offset.first);
      CAPTURE(p);
      const detail::LightReach fresh = detail::compute_light_reach(prepared, p, scratch);
      const detail::LightReach& held = cache.reach()[p];
      CHECK(held.reach == fresh.reach);
      CHECK(held.nearest == fresh.nearest);
      CHECK(held.farthest == fresh.farthest);
    }
  }
  CHECK(kept > 0);    // small pans re-prove nothing
  CHECK(proven > 0);  // far jumps re-prove some lights
}


// The frame engine deals blocks (and the bounce stage's parts and coarse nodes) to its lanes as
// they finish, so which lane computes which block changes from frame to frame and from run to
// run. Whatever lane a block falls to and whatever that lane computed before, the frame's bytes
// and counts must be those of one thread.
TEST_CASE("blocks taken by the lanes as they finish: two threads give one thread's bytes and counts, frame after frame") {
  std::vector<RenderOptions> variants;
  RenderOptions scalar;
  scalar.backend = Backend::scalar;
  variants.push_back(scalar);
  for (Isa isa : kernel_isas()) {
    RenderOptions o;
    o.backend = Backend::simd;
    o.isa = isa;
    variants.push_back(o);
  }
  struct Case {
    std::uint32_t seed;
    bool albedo;   // the bounce stage and its parts
    int step;      // a coarse bounce (> 1): its nodes in groups
    int width;     // 200: 12 blocks; 40: one block, fewer than the lanes
    bool layered;  // incremental with a light-layer cache, a light moving each frame
  };
  const Case cases[] = {{71u, false, 1, 200, false}, {72u, true, 1, 200, false}, {73u, true, 4, 200, false},
                        {74u, false, 1, 40, false},  {75u, true, 2, 40, false},  {76u, false, 1, 200, true}};
  for (const Case& c : cases) {
    Scene scene = plan_scene(c.seed, c.albedo);
    scene.bounce.step = c.step;
    scene.width = c.width;
    scene.height = c.width == 200 ? 140 : 30;
    scene.view = View{0.0, 0.0, static_cast<double>(scene.width), static_cast<double>(scene.height)};
    REQUIRE(validate_scene(scene).ok());
    for (RenderOptions options : variants) {
      // Layers hold what a kernel computes; the scalar reference's bounce over 12 blocks is the
      // costliest case here and deals as the kernel's does.
      if (options.backend == Backend::scalar && (c.layered || (c.albedo && c.width == 200))) continue;
      CAPTURE(c.seed);
      INFO("backend ", std::string(backend_name(options.backend)), " isa ",
           std::string(options.isa ? isa_name(*options.isa) : "-"));
      options.sample_needs = true;
      const std::size_t floats = static_cast<std::size_t>(scene.width) * static_cast<std::size_t>(scene.height) * 3;
      Renderer r[2];
      std::vector<LightHandle> handles[2];
      std::vector<float> pixels[2] = {std::vector<float>(floats), std::vector<float>(floats)};
      for (int i = 0; i < 2; ++i) {
        options.threads = 1 + i;
        REQUIRE(r[i].set_options(options).ok());
        REQUIRE(r[i].set_scene(scene, &handles[i]).ok());
        if (c.layered) {
          REQUIRE(r[i].set_incremental(true).ok());
          REQUIRE(r[i].set_light_layer_budget(std::size_t{16} << 20).ok());
        }
      }
      for (int frame = 0; frame < 3; ++frame) {
        CAPTURE(frame);
        for (int i = 0; i < 2; ++i) {
          if (c.layered && frame > 0) {  // one light moves a little: some blocks layered, some recombined
            Transform t;
            t.position = Vec2{3.0 * frame, -2.0 * frame};
            REQUIRE(r[i].update_light(handles[i][0], scene.lights[0], t).ok());
          }
          REQUIRE(r[i].render(ImageView{pixels[i].data(), scene.width, scene.height, scene.width * 3}).ok());
        }
        CHECK(std::memcmp(pixels[0].data(), pixels[1].data(), floats * sizeof(float)) == 0);
        const FrameCounts one = frame_counts(r[0]), two = frame_counts(r[1]);
        CHECK(one.tiles > 0u);
        CHECK(two.tiles == one.tiles);
        CHECK(two.blocks == one.blocks);
        CHECK(two.tile_lights == one.tile_lights);
        CHECK(two.bounce_source_walks == one.bounce_source_walks);
        CHECK(two.layer_tiles_reused == one.layer_tiles_reused);
        CHECK(std::memcmp(static_cast<const FrameStats*>(&one), static_cast<const FrameStats*>(&two), sizeof(FrameStats)) == 0);
        CHECK(std::memcmp(static_cast<const FrameDiagnostics*>(&one), static_cast<const FrameDiagnostics*>(&two),
                          sizeof(FrameDiagnostics)) == 0);
      }
    }
  }
}


#if !PAR2D_STD_THREADS
// A one-shot render makes a scheduler per frame; its arena is kept when the scheduler goes and
// handed to the next scheduler of the same thread count (a fresh arena per frame mostly got no
// worker thread), one scheduler at a time.
TEST_CASE("idle arenas: an arena given back is taken by the next scheduler of its thread count, by one at a time") {
  // Whatever earlier tests left idle is taken first, so that the pool holds only what follows.
  std::vector<std::unique_ptr<tbb::task_arena>> earlier;
  for (int threads = 1; threads <= 2; ++threads)
    for (int k = 0; k < 16; ++k) earlier.push_back(detail::IdleArenas::take(threads));
  auto two = std::make_unique<tbb::task_arena>(2);
  two->initialize();
  tbb::task_arena* const kept = two.get();
  detail::IdleArenas::give(2, std::move(two));
  std::unique_ptr<tbb::task_arena> other = detail::IdleArenas::take(1);  // another count: a new one
  CHECK(other.get() != kept);
  CHECK(other->max_concurrency() == 1);
  std::unique_ptr<tbb::task_arena> again = detail::IdleArenas::take(2);
  CHECK(again.get() == kept);
  std::unique_ptr<tbb::task_arena> fresh = detail::IdleArenas::take(2);  // the kept one is in use
  CHECK(fresh.get() != kept);
  CHECK(fresh->max_concurrency() == 2);
  // Schedulers one after another, each on the arena the last gave back: every index once,
  // on a worker index of its own arena.
  for (int frame = 0; frame < 40; ++frame) {
    detail::Scheduler scheduler;
    scheduler.configure(2, Threading::own_pool);
    std::vector<int> seen(64, 0);
    std::atomic<bool> outside{false};
    scheduler.for_each_index(64, [&](int i, int worker) {
      if (worker < 0 || worker >= 2) outside.store(true);
      ++seen[static_cast<std::size_t>(i)];
    });
    CHECK_FALSE(outside.load());
    CHECK(std::count(seen.begin(), seen.end(), 1) == 64);
  }
}
#endif

}  // namespace par2d::test
