// One front door: one-shot render() is a Renderer's frame (every pixel format), the sampled
// needs are a Renderer option, the ray caster is the named baseline render_raycast, and the
// reach cache in culling follows the World's change events exactly (a light's reach after any
// change sequence equals the reach proven from scratch for the same world).
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "culling/light_reach.hpp"
#include "culling/reach_cache.hpp"
#include "par2d/par2d.hpp"
#include "parallel/scheduler.hpp"
#include "support/random_scenes.hpp"
#include "support/test_tiers.hpp"
#include "world/world.hpp"

using namespace par2d;

namespace {

std::vector<float> rgb_frame(const Scene& scene) {
  return std::vector<float>(static_cast<std::size_t>(scene.width) * static_cast<std::size_t>(scene.height) * 3, -1.0f);
}

ImageView view_of(std::vector<float>& pixels, const Scene& scene) {
  return {pixels.data(), scene.width, scene.height, 3 * static_cast<std::ptrdiff_t>(scene.width)};
}

}  // namespace

TEST_CASE("one-shot render in every pixel format equals a Renderer's frame byte for byte" * test::per_isa()) {
  for (std::uint32_t seed : {3u, 11u}) {
    test::RandomSceneOptions options;
    const Scene scene = test::random_scene(seed, options);
    Renderer renderer;
    REQUIRE(renderer.set_scene(scene).ok());
    for (PixelFormat format : {PixelFormat::rgb_f32, PixelFormat::rgba_f32, PixelFormat::rgba8_srgb}) {
      const int pixel = bytes_per_pixel(format);
      const std::size_t bytes = static_cast<std::size_t>(scene.width) * static_cast<std::size_t>(scene.height) * pixel;
      std::vector<unsigned char> once(bytes, 0xAB), kept(bytes, 0xCD);
      FrameBuffer a{once.data(), format, static_cast<std::ptrdiff_t>(scene.width) * pixel, 2.0};
      FrameBuffer b{kept.data(), format, static_cast<std::ptrdiff_t>(scene.width) * pixel, 2.0};
      REQUIRE(render(scene, RenderOptions{}, a).ok());
      REQUIRE(renderer.render(b).ok());
      CHECK(std::memcmp(once.data(), kept.data(), bytes) == 0);
    }
  }
}

TEST_CASE("the sampled needs come from a Renderer with sample_needs only, into its FrameDiagnostics" *
          test::per_isa()) {
  const Scene scene = test::random_scene(5);
  std::vector<float> pixels = rgb_frame(scene);
  Renderer renderer;
  REQUIRE(renderer.set_scene(scene).ok());
  REQUIRE(renderer.render(view_of(pixels, scene)).ok());
  const FrameDiagnostics plain = renderer.frame_diagnostics();
  CHECK(plain.sampled_pixels == 0);  // off by default
  RenderOptions needs;
  needs.sample_needs = true;
  REQUIRE(renderer.set_options(needs).ok());
  REQUIRE(renderer.render(view_of(pixels, scene)).ok());
  const FrameDiagnostics sampled = renderer.frame_diagnostics();
  // The scalar reference (PAR2D_ISA=scalar) counts no needs; the SIMD path one pixel per tile.
  CHECK((sampled.sampled_pixels == renderer.frame_stats().tiles) == (resolved_isa(needs) != Isa::scalar));
  CHECK(sampled.tile_pairs == plain.tile_pairs);  // the sampling changes no other count
  CHECK(sampled.blocks == plain.blocks);
}

TEST_CASE("the ray caster is render_raycast alone: no Backend names it, so no Renderer can be given it; it renders one-shot, with progress, and checks its rays") {
  // Backend holds what a Renderer runs, each name parsing back; "raycast" is none of them, and
  // a value past the last is refused as no backend.
  for (const Backend b : {Backend::automatic, Backend::simd, Backend::scalar}) CHECK(parse_backend(backend_name(b)) == b);
  CHECK(!parse_backend("raycast"));
  RenderOptions past;
  past.backend = static_cast<Backend>(static_cast<int>(Backend::scalar) + 1);
  Renderer renderer;
  const Status refused = renderer.set_options(past);
  CHECK(refused.code() == StatusCode::invalid_argument);
  CHECK(refused.message() == "set_options: unknown backend 3");

  const Scene scene = test::random_scene(7);
  RenderOptions options;
  options.rays = 64;
  std::vector<float> plain = rgb_frame(scene), watched = rgb_frame(scene);
  REQUIRE(render_raycast(scene, options, view_of(plain, scene)).ok());
  CHECK(*std::max_element(plain.begin(), plain.end()) > 0.0f);
  // Watched, the frame is computed aside and copied out once complete: the same bytes, its
  // tiles reported up to all of them.
  RenderControl control;
  std::uint64_t done = 0, tiles = 0;
  control.progress = [&](const Progress& p) {
    done = p.tiles_done;
    tiles = p.tiles;
    return true;
  };
  REQUIRE(render_raycast(scene, options, view_of(watched, scene), control).ok());
  CHECK(std::memcmp(plain.data(), watched.data(), plain.size() * sizeof(float)) == 0);
  CHECK(tiles > 0u);
  CHECK(done == tiles);
  WorkEstimate estimate;
  REQUIRE(estimate_raycast_work(scene, options, estimate).ok());
  CHECK(estimate.raycast > 0.0);
  CHECK(estimate.scalar == 0.0);

  options.rays = 0;
  const Status bad_rays = render_raycast(scene, options, view_of(plain, scene));
  CHECK(bad_rays.message() == "render_raycast: rays must be in 1..1048576");
  CHECK(estimate_raycast_work(scene, options, estimate).message() == "estimate_raycast_work: rays must be in 1..1048576");
  options.rays = 64;
  std::vector<float> small(12);
  const Status bad_size = render_raycast(scene, options, ImageView{small.data(), 2, 2, 6});
  CHECK(bad_size.message() == "render_raycast: image is 2x2 but the scene is " + std::to_string(scene.width) + "x" +
                                  std::to_string(scene.height));
}

TEST_CASE("the reach cache follows the World's events: after random changes every light's reach equals a fresh proof") {
  // Lights and walls in a 512x384 frame, some walls much longer than the frame; random adds,
  // moves, reshapes, emission changes and removals between commits. After each commit, every light's cached reach must equal the
  // reach proven from scratch on the same prepared scene (a missed event leaves a stale one).
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> x(0.0, 512.0), y(0.0, 384.0), size(2.0, 24.0);
  // One wall in eight is much longer than the frame (either way): its box sticks out of the
  // box a proof looked in, which it may still cross.
  auto wall = [&] {
    const double x0 = x(rng), y0 = y(rng);
    Occluder o;
    if (rng() % 8 == 0) {
      const double half = 2000.0 + 20.0 * size(rng);
      o.shape = rng() % 2 ? Polygon{{{x0 - half, y0}, {x0 + half, y0}, {x0 + half, y0 + 3.0}, {x0 - half, y0 + 3.0}}}
                          : Polygon{{{x0, y0 - half}, {x0 + 3.0, y0 - half}, {x0 + 3.0, y0 + half}, {x0, y0 + half}}};
      return o;
    }
    o.shape = Polygon{{{x0, y0}, {x0 + size(rng), y0}, {x0 + size(rng), y0 + size(rng)}, {x0, y0 + 3.0}}};
    return o;
  };
  auto torch = [&] {
    Light l;
    l.shape = Circle{{x(rng), y(rng)}, 1.0 + size(rng) / 8.0};
    return l;
  };
  Scene scene;
  scene.width = 512;
  scene.height = 384;
  scene.view = {0, 0, 512, 384};
  for (int i = 0; i < 6; ++i) scene.lights.push_back(torch());
  for (int i = 0; i < 60; ++i) scene.occluders.push_back(wall());

  detail::ReachCache cache;
  detail::World world;
  world.observe(&cache);
  std::vector<LightHandle> lights;
  std::vector<OccluderHandle> occluders;
  REQUIRE(world.set_scene(scene, &lights, &occluders).ok());
  detail::Scheduler scheduler;
  scheduler.configure(1, Threading::own_pool);
  detail::LightReachScratch scratch;
  std::size_t proven = 0;
  for (int step = 0; step < 40; ++step) {
    const int changes = 1 + static_cast<int>(rng() % 4);
    for (int c = 0; c < changes; ++c) {
      switch (rng() % 7) {
        case 0: {
          LightHandle h;
          REQUIRE(world.add_light(torch(), &h).ok());
          lights.push_back(h);
          break;
        }
        case 1:
          if (lights.size() > 1) {
            const std::size_t i = rng() % lights.size();
            REQUIRE(world.remove_light(lights[i]).ok());
            lights.erase(lights.begin() + static_cast<std::ptrdiff_t>(i));
          }
          break;
        case 2: REQUIRE(world.update_light(lights[rng() % lights.size()], torch()).ok()); break;
        case 3: REQUIRE(world.set_light_emission(lights[rng() % lights.size()], {1, 1, 1}, 0.5 * static_cast<double>(rng() % 3)).ok()); break;
        case 4: REQUIRE(world.update_occluder(occluders[rng() % occluders.size()], wall()).ok()); break;
        case 5: {
          OccluderHandle h;
          REQUIRE(world.add_occluder(wall(), &h).ok());
          occluders.push_back(h);
          break;
        }
        default:
          if (occluders.size() > 1) {
            const std::size_t i = rng() % occluders.size();
            REQUIRE(world.remove_occluder(occluders[i]).ok());
            occluders.erase(occluders.begin() + static_cast<std::ptrdiff_t>(i));
          }
      }
    }
    if (step % 10 == 9) REQUIRE(world.set_frame(512, 384, View{0.0, 0.0, 512.0 + step, 384.0}).ok());
    const detail::PreparedScene& prepared = world.commit();
    proven += cache.update(prepared, scheduler);
    REQUIRE(cache.reach().size() == prepared.lights.size());
    for (std::size_t p = 0; p < prepared.lights.size(); ++p) {
      const detail::LightReach fresh = detail::compute_light_reach(prepared, p, scratch);
      const detail::LightReach& kept = cache.reach()[p];
      CHECK(kept.center.x == fresh.center.x);
      CHECK(kept.center.y == fresh.center.y);
      CHECK(kept.radius == fresh.radius);
      CHECK(kept.reach == fresh.reach);
    }
  }
  // The cache proves only what changed: far fewer proofs than lights x commits.
  CHECK(proven < 40 * 6);
}
