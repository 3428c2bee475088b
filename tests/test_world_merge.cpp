// Tilemap boxes merged inside the World behind unchanged handles (world/world_merge.cpp):
// one entry per run of boxes, every handle still naming its own box, and through any sequence
// of edits the groups stay what merging the current boxes gives, so a Renderer's frame is bit
// for bit a one-shot render of its snapshot.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "grid_levels.hpp"
#include "par2d/renderer.hpp"
#include "par2d/scene_write.hpp"
#include "support/random_scenes.hpp"
#include "support/render_checks.hpp"
#include "support/test_tiers.hpp"
#include "world/occluder_merge.hpp"
#include "world/world.hpp"

using namespace par2d;
using par2d::test::frame_rgb;
using par2d::test::one_shot;
using par2d::test::same_bits;

namespace {

Occluder box(double x0, double y0, double x1, double y1) {
  return Occluder{Polygon{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}}};
}

Scene tilemap(double tile) {
  bench::WallLevel level;
  level.width = 256;
  level.height = 160;
  level.tile = tile;
  level.torches = 4;
  level.overlap = 1.0;
  return bench::wall_level(level);
}

// An occluder as comparable text (every property, exactly).
std::string text(const Occluder& o) {
  Scene one;
  one.width = 1;
  one.height = 1;
  one.view = {0, 0, 1, 1};
  one.occluders = {o};
  return scene_to_json(one);
}

// A scene's occluders as text, in a canonical order (snapshot order is not the scene's).
std::vector<std::string> occluder_texts(const Scene& scene) {
  std::vector<std::string> out;
  for (const Occluder& o : scene.occluders) out.push_back(text(o));
  std::sort(out.begin(), out.end());
  return out;
}




}  // namespace

TEST_CASE("world merging: a tilemap is one entry per run, and every handle still names its own box") {
  for (const double tile : {16.0, 32.0}) {
    const Scene level = tilemap(tile);
    detail::World world;
    std::vector<OccluderHandle> handles;
    REQUIRE(world.set_scene(level, nullptr, &handles).ok());
    const std::size_t runs = detail::merge_tilemap_boxes(level.occluders).size();
    CAPTURE(tile);
    CHECK(runs < level.occluders.size() / 2);  // the level is mostly wall rows
    CHECK(world.prepared().occluders.size() == runs);
    CHECK(world.occluder_count() == level.occluders.size());
    REQUIRE(handles.size() == level.occluders.size());
    for (std::size_t i = 0; i < handles.size(); ++i) {
      const Occluder* o = world.find_occluder(handles[i].id);
      REQUIRE(o != nullptr);
      CHECK(text(*o) == text(level.occluders[i]));
    }
    CHECK(occluder_texts(world.snapshot()) == occluder_texts(level));
  }
}

TEST_CASE("world merging: 300 random edits of a tilemap keep the groups canonical and frames a one-shot render" *
          par2d::test::per_isa()) {
  for (const unsigned seed : {3901u, 6u, 7u}) {
    CAPTURE(seed);
    Scene level = tilemap(16.0);
    // A ranged light with a steep falloff: its pixels weigh the boxes' edges unevenly.
    Light ranged{Circle{{100.0, 70.0}, 3.0}, {1.0, 0.8, 0.6}, 2.0};
    ranged.range = 90.0;
    ranged.falloff = 16.0;
    level.lights.push_back(ranged);
    Renderer r;
    RenderOptions options;
    options.threads = 2;
    REQUIRE(r.set_options(options).ok());
    std::vector<OccluderHandle> handles;
    REQUIRE(r.set_scene(level, nullptr, &handles).ok());
    // The World beside it takes the same edits, to look at its entries.
    detail::World world;
    std::vector<OccluderHandle> world_handles;
    REQUIRE(world.set_scene(level, nullptr, &world_handles).ok());
    // An incremental Renderer beside it, rendering after every edit: only the blocks the
    // edits (and the regrouping they cause) mark are computed, and its buffer must still be
    // a full render's, byte for byte.
    Renderer inc;
    REQUIRE(inc.set_options(options).ok());
    std::vector<OccluderHandle> inc_handles;
    REQUIRE(inc.set_scene(level, nullptr, &inc_handles).ok());
    REQUIRE(inc.set_incremental(true).ok());
    std::vector<float> inc_pixels(static_cast<std::size_t>(inc.width()) * inc.height() * 3, -1.0f);
    const ImageView inc_view{inc_pixels.data(), inc.width(), inc.height(),
                             static_cast<std::ptrdiff_t>(inc.width()) * 3};
    std::vector<Occluder> shapes = level.occluders;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int checked_frames = 0, grouped_edits = 0;
    for (int step = 0; step < 300; ++step) {
      CAPTURE(step);
      const double what = unit(rng);
      CAPTURE(what);
      CAPTURE(what);
      if (what < 0.15 || handles.empty()) {
        // A box on the tile grid (it may complete or extend a run) or, at times, off it; one or
        // two tiles long, or half a tile along: boxes of a row overlap, contain one another and
        // start where others do.
        const double tile = 16.0;
        const double x = tile * std::floor(unit(rng) * 16.0), y = tile * std::floor(unit(rng) * 10.0);
        const double pick = unit(rng);
        const double off = pick < 0.15 ? 3.0 : pick < 0.3 ? 0.5 * tile : 0.0;
        const double length = unit(rng) < 0.3 ? 2.0 * tile : tile;
        Occluder o = box(x + off, y, x + off + length, y + tile);
        OccluderHandle h, wh;
        OccluderHandle ih;
        REQUIRE(r.add_occluder(o, &h).ok());
        REQUIRE(world.add_occluder(o, &wh).ok());
        REQUIRE(inc.add_occluder(o, &ih).ok());
        handles.push_back(h);
        world_handles.push_back(wh);
        inc_handles.push_back(ih);
        shapes.push_back(o);
      } else {
        const auto i = static_cast<std::size_t>(unit(rng) * static_cast<double>(handles.size()));
        if (what < 0.35) {
          REQUIRE(r.remove_occluder(handles[i]).ok());
          REQUIRE(world.remove_occluder(world_handles[i]).ok());
          REQUIRE(inc.remove_occluder(inc_handles[i]).ok());
          handles.erase(handles.begin() + static_cast<std::ptrdiff_t>(i));
          world_handles.erase(world_handles.begin() + static_cast<std::ptrdiff_t>(i));
          inc_handles.erase(inc_handles.begin() + static_cast<std::ptrdiff_t>(i));
          shapes.erase(shapes.begin() + static_cast<std::ptrdiff_t>(i));
        } else {
          Occluder o = shapes[i];
          if (what < 0.45) {
            o.mask = o.mask == kAllMaskBits ? 1u : kAllMaskBits;  // leaves runs of other masks
          } else if (what < 0.55) {
            o.shape =
                Circle{{16.0 * std::floor(unit(rng) * 16.0) + 8.0, 16.0 * std::floor(unit(rng) * 10.0) + 8.0}, 5.0};
          } else {
            // By whole tiles (may join another run) or by a fraction (joins none).
            const double dx = 16.0 * std::floor(unit(rng) * 5.0 - 2.0) + (unit(rng) < 0.3 ? 1.5 : 0.0);
            const double dy = unit(rng) < 0.5 ? 0.0 : 16.0 * std::floor(unit(rng) * 3.0 - 1.0);
            auto* p = std::get_if<Polygon>(&o.shape);
            if (p) {
              for (Vec2& v : p->vertices) v = {v.x + dx, v.y + dy};
            } else {
              o = box(16.0 * std::floor(unit(rng) * 16.0), 16.0 * std::floor(unit(rng) * 10.0), 0, 0);
              auto& q = std::get<Polygon>(o.shape).vertices;
              q[1].x = q[2].x = q[0].x + 16.0;
              q[2].y = q[3].y = q[0].y + 16.0;
            }
          }
          REQUIRE(r.update_occluder(handles[i], o).ok());
          REQUIRE(world.update_occluder(world_handles[i], o).ok());
          REQUIRE(inc.update_occluder(inc_handles[i], o).ok());
          shapes[i] = o;
        }
      }
      // The World's entries are what merging the current boxes gives, and each handle names its box.
      const Scene snapshot = world.snapshot();
      const std::size_t runs = detail::merge_tilemap_boxes(snapshot.occluders).size();
      REQUIRE(world.prepared().occluders.size() == runs);
      REQUIRE(world.occluder_count() == shapes.size());
      grouped_edits += runs < shapes.size();
      for (std::size_t k = 0; k < handles.size(); ++k) {
        Occluder o;
        REQUIRE(r.occluder(handles[k], &o).ok());
        REQUIRE(text(o) == text(shapes[k]));
      }
      REQUIRE(inc.render(inc_view).ok());
      if (step % 15 == 14) {
        const std::vector<float> full = one_shot(r.snapshot(), r.options());
        REQUIRE(same_bits(frame_rgb(r), full));
        REQUIRE(same_bits(inc_pixels, full));
        ++checked_frames;
      }
    }
    CHECK(checked_frames == 20);
    // Merging is exercised through most of the sequence (edits remove and scatter boxes, so
    // at times no run is left).
    CHECK(grouped_edits >= 250);
  }
}

// Boxes of one row that start where another starts ([112, 128] inside [112, 144]) could
// continue the same run; which one does must follow from the boxes, not from their order:
// the World regroups in its snapshot order, which forming a group changes, and a load of the
// snapshot then merged the other box (other entries: 8 pixels off by 1e-5 relative). Every
// order of adding them, a twin of one, and removing and adding one again must give the
// merging of the snapshot and its one-shot render, bit for bit.
TEST_CASE("world merging: overlapping and contained boxes of a row merge alike whatever the order of edits" *
          par2d::test::per_isa()) {
  const std::vector<Occluder> row = {box(112, 64, 144, 80), box(112, 64, 128, 80), box(96, 64, 112, 80),
                                     box(112, 64, 128, 80)};
  Light ranged{Circle{{120.0, 100.0}, 4.0}, {1.0, 0.9, 0.8}, 1.5};
  ranged.range = 80.0;
  ranged.falloff = 16.0;
  for (const std::size_t boxes : {std::size_t{3}, std::size_t{4}}) {  // without and with the twin
    std::vector<std::size_t> order(boxes);
    for (std::size_t i = 0; i < boxes; ++i) order[i] = i;
    do {
      CAPTURE(boxes);
      CAPTURE(order[0]);
      CAPTURE(order[1]);
      CAPTURE(order[2]);
      Renderer r;
      RenderOptions options;
      options.threads = 2;
      REQUIRE(r.set_options(options).ok());
      REQUIRE(r.set_frame(256, 160).ok());
      LightHandle light;
      REQUIRE(r.add_light(ranged, &light).ok());
      detail::World world;  // the same edits, to look at its entries
      REQUIRE(world.set_frame(256, 160, View{0, 0, 256, 160}).ok());
      std::vector<OccluderHandle> handles, world_handles;
      for (const std::size_t i : order) {
        OccluderHandle h, wh;
        REQUIRE(r.add_occluder(row[i], &h).ok());
        REQUIRE(world.add_occluder(row[i], &wh).ok());
        handles.push_back(h);
        world_handles.push_back(wh);
      }
      auto check_frame = [&](const std::string& step) {
        INFO(step);
        const Scene snapshot = world.snapshot();
        CHECK(world.prepared().occluders.size() == detail::merge_tilemap_boxes(snapshot.occluders).size());
        CHECK(same_bits(frame_rgb(r), one_shot(r.snapshot(), r.options())));
      };
      check_frame("added");
      REQUIRE(r.remove_occluder(handles[0]).ok());
      REQUIRE(world.remove_occluder(world_handles[0]).ok());
      check_frame("the first added removed");
      REQUIRE(r.add_occluder(row[order[0]], &handles[0]).ok());
      REQUIRE(world.add_occluder(row[order[0]], &world_handles[0]).ok());
      check_frame("added again");
    } while (std::next_permutation(order.begin(), order.end()));
  }
}

TEST_CASE("world merging: the runs of a list of boxes follow from the boxes, not from their order") {
  // Rows of boxes on a half-tile grid, one or two tiles long: they overlap, contain one another,
  // share starts and ends, and some are given twice.
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Occluder> boxes;
  for (int i = 0; i < 60; ++i) {
    const double x = 8.0 * std::floor(unit(rng) * 12.0), y = 16.0 * std::floor(unit(rng) * 3.0);
    boxes.push_back(box(x, y, x + (unit(rng) < 0.4 ? 32.0 : 16.0), y + 16.0));
    if (unit(rng) < 0.1) boxes.push_back(boxes.back());
  }
  // The merged list as sorted texts of each group's boxes and union: the same for every order.
  auto groups = [](const std::vector<Occluder>& list) {
    std::vector<std::string> out;
    for (const detail::MergedOccluder& m : detail::merge_tilemap_boxes(list)) {
      std::vector<std::string> members;
      for (const std::size_t k : m.sources) members.push_back(text(list[k]));
      std::sort(members.begin(), members.end());
      std::string group = text(m.occluder);
      for (const std::string& member : members) group += member;
      out.push_back(group);
    }
    std::sort(out.begin(), out.end());
    return out;
  };
  const std::vector<std::string> expected = groups(boxes);
  CHECK(expected.size() < boxes.size());  // some runs formed
  for (int shuffle = 0; shuffle < 20; ++shuffle) {
    CAPTURE(shuffle);
    std::shuffle(boxes.begin(), boxes.end(), rng);
    CHECK(groups(boxes) == expected);
  }
}

TEST_CASE("world merging: moving one wall box splits its run once; it then moves as a box of its own") {
  const Scene level = tilemap(32.0);
  detail::World world;
  std::vector<OccluderHandle> handles;
  REQUIRE(world.set_scene(level, nullptr, &handles).ok());
  // A box of the top wall row (y from 0 to 32), not at either end.
  std::size_t cell = level.occluders.size();
  for (std::size_t i = 0; i < level.occluders.size(); ++i) {
    const auto& v = std::get<Polygon>(level.occluders[i].shape).vertices;
    if (v[0].y == 0.0 && v[2].y == 32.0 && v[0].x == 96.0) cell = i;
  }
  REQUIRE(cell < level.occluders.size());
  const std::size_t entries = world.prepared().occluders.size();
  Occluder o = level.occluders[cell];
  for (Vec2& v : std::get<Polygon>(o.shape).vertices) v.y += 40.5;  // into the room, off the grid
  const std::uint64_t before = world.stats().index_updates;
  REQUIRE(world.update_occluder(handles[cell], o).ok());
  // The row is now two runs and the box: two entries more.
  CHECK(world.prepared().occluders.size() == entries + 2);
  const std::uint64_t split = world.stats().index_updates - before;
  MESSAGE("index updates to split the row: ", split);
  for (Vec2& v : std::get<Polygon>(o.shape).vertices) v.x += 3.0;
  REQUIRE(world.update_occluder(handles[cell], o).ok());
  CHECK(world.stats().index_updates - before == split + 1);
  // Back in its place: the row is one run again.
  o = level.occluders[cell];
  REQUIRE(world.update_occluder(handles[cell], o).ok());
  CHECK(world.prepared().occluders.size() == entries);
}
