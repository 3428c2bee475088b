// The change tracker: events mark lights and regions, plan turns them into dirty blocks.
#include "render/change_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "render/block_culling.hpp"
#include "render/kernel_shapes.hpp"
#include "render/tiling.hpp"

namespace par2d::detail {
namespace {

bool same_view(const View& a, const View& b) noexcept {
  return a.x0 == b.x0 && a.y0 == b.y0 && a.x1 == b.x1 && a.y1 == b.y1;
}

bool same_reach(const LightReach& a, const LightReach& b) noexcept {
  return a.center.x == b.center.x && a.center.y == b.center.y && a.radius == b.radius && a.reach == b.reach &&
         a.nearest == b.nearest && a.farthest == b.farthest;
}

bool same_box(const Aabb& a, const Aabb& b) noexcept {
  return a.min_x == b.min_x && a.min_y == b.min_y && a.max_x == b.max_x && a.max_y == b.max_y;
}

bool empty_box(const Aabb& b) noexcept { return !(b.min_x <= b.max_x && b.min_y <= b.max_y); }

Aabb intersection(const Aabb& a, const Aabb& b) noexcept {
  return {std::max(a.min_x, b.min_x), std::max(a.min_y, b.min_y), std::min(a.max_x, b.max_x),
          std::min(a.max_y, b.max_y)};
}

}  // namespace

bool FrameKey::operator==(const FrameKey& o) const noexcept {
  return width == o.width && height == o.height && same_view(view, o.view) && scale == o.scale && far == o.far &&
         trusted == o.trusted && extent == o.extent && model == o.model && bounce == o.bounce &&
         scrolls == o.scrolls && ring == o.ring && data == o.data && format == o.format &&
         row_stride == o.row_stride && exposure == o.exposure && settings.spp == o.settings.spp &&
         settings.culling == o.settings.culling && settings.isa == o.settings.isa &&
         settings.shaded == o.settings.shaded && settings.sample_needs == o.settings.sample_needs &&
         settings.bounce == o.settings.bounce;
}

void ChangeTracker::lights_reset(std::size_t count) noexcept {
  full_ = true;
  any_ = true;
  if (next_) next_->lights_reset(count);
}

void ChangeTracker::light_added() {
  if (next_) next_->light_added();
  any_ = true;
  if (full_) return;  // the arrays are rebuilt at the next frame
  old_.emplace_back();
  changed_.push_back(kChanged);
}

void ChangeTracker::light_changed(std::size_t p) noexcept {
  if (next_) next_->light_changed(p);
  any_ = true;
  if (!full_ && p < changed_.size()) changed_[p] |= kChanged;
}

void ChangeTracker::light_emission_changed(std::size_t p) noexcept {
  if (next_) next_->light_emission_changed(p);
  any_ = true;
  if (!full_ && p < changed_.size()) changed_[p] |= kEmission;
}

void ChangeTracker::light_erased(std::size_t p) noexcept {
  if (next_) next_->light_erased(p);
  any_ = true;
  // The lights above keep their order (a tile sums its lights in number order), so their
  // pixels and layers stay: only their numbers move down.
  if (layers_) layers_->erase_light(p);
  if (full_ || p >= changed_.size()) {
    full_ = true;
    return;
  }
  // The erased light's pixels.
  if (!empty_box(old_[p].influence)) {
    if (erased_.size() == erased_.capacity()) {
      full_ = true;  // no allocation here
      return;
    }
    erased_.push_back(old_[p]);
  }
  const auto at = static_cast<std::ptrdiff_t>(p);
  old_.erase(old_.begin() + at);
  changed_.erase(changed_.begin() + at);
}

void ChangeTracker::region(const Aabb& box) noexcept {
  any_ = true;
  if (full_) return;
  if (regions_.size() == regions_.capacity()) {
    full_ = true;
    return;
  }
  regions_.push_back(box);
}

void ChangeTracker::region_changed(const Aabb& box) noexcept {
  if (next_) next_->region_changed(box);
  region(box);
}

void ChangeTracker::occluder_renumbered(const Aabb& box) noexcept {
  if (next_) next_->occluder_renumbered(box);
  region(box);
}

void ChangeTracker::frame_changed() noexcept {
  if (next_) next_->frame_changed();
  full_ = true;
  any_ = true;
}

void ChangeTracker::frame_scrolled() noexcept {
  // Nothing to mark: plan compares the frame's offset with the last one's.
  if (next_) next_->frame_scrolled();
}

void ChangeTracker::terms_changed() noexcept {
  if (next_) next_->terms_changed();
  full_ = true;
  any_ = true;
}

bool ChangeTracker::Footprint::takes_part(const Aabb& box, bool model) const noexcept {
  if (empty_box(influence) || !boxes_meet(influence, box) || reach.hides(box)) return false;
  if (!model || !(range < std::numeric_limits<double>::infinity())) return true;
  // beyond_range (render/model_terms.hpp) on the shape's box, as cull_block tests it.
  const double dx = std::max({bounds.min_x - box.max_x, 0.0, box.min_x - bounds.max_x});
  const double dy = std::max({bounds.min_y - box.max_y, 0.0, box.min_y - bounds.max_y});
  return !(std::hypot(dx, dy) >= range);
}

// Marks every block that meets `box` (prepared coordinates), with a pixel to spare.
void ChangeTracker::mark(const PreparedScene& scene, const Aabb& box) {
  if (empty_box(box)) return;
  const BlockGrid grid = frame_blocks(scene);
  // Pixel coordinates of the box's sides (either axis may run either way).
  const View view = scene.visible_view();
  const double sx = scene.width / (view.x1 - view.x0);
  const double sy = scene.height / (view.y1 - view.y0);
  double px0 = (box.min_x - view.x0) * sx, px1 = (box.max_x - view.x0) * sx;
  double py0 = (box.min_y - view.y0) * sy, py1 = (box.max_y - view.y0) * sy;
  if (std::isnan(px0) || std::isnan(px1) || std::isnan(py0) || std::isnan(py1)) {
    std::fill(mask_.begin(), mask_.end(), kBlockWhole);
    if (layered_) layers_->clear();
    return;
  }
  if (px0 > px1) std::swap(px0, px1);
  if (py0 > py1) std::swap(py0, py1);
  if (!(px1 >= -2.0 && py1 >= -2.0 && px0 <= scene.width + 2.0 && py0 <= scene.height + 2.0)) return;
  const auto block_of = [](double p, int anchor, int count) {
    const double b = std::floor((p + anchor) / kBlockSize);
    return static_cast<int>(std::clamp(b, 0.0, static_cast<double>(count - 1)));
  };
  const int bx0 = block_of(px0 - 1.0, grid.ax, grid.columns), bx1 = block_of(px1 + 1.0, grid.ax, grid.columns);
  const int by0 = block_of(py0 - 1.0, grid.ay, grid.rows), by1 = block_of(py1 + 1.0, grid.ay, grid.rows);
  for (int by = by0; by <= by1; ++by) {
    std::fill(mask_.begin() + by * grid.columns + bx0, mask_.begin() + by * grid.columns + bx1 + 1, kBlockWhole);
    if (layered_)
      for (int bx = bx0; bx <= bx1; ++bx) layers_->drop_block(static_cast<std::size_t>(by * grid.columns + bx));
  }
}

void ChangeTracker::plan_scroll(const PreparedScene& scene, int dx, int dy) {
  const BlockGrid grid = frame_blocks(scene);
  const int w = scene.width, h = scene.height;
  // The bands, widened to the tiles that hold them (whole tiles are computed).
  const auto tile_floor = [](int p, int anchor) { return (p + anchor) / kTileSize * kTileSize - anchor; };
  const auto tile_ceil = [](int p, int anchor) { return (p + anchor + kTileSize - 1) / kTileSize * kTileSize - anchor; };
  uncovered_ = UncoveredPixels{};
  if (dx > 0) uncovered_.columns = {std::max(0, tile_floor(w - dx, grid.ax)), 0, w, h};
  if (dx < 0) uncovered_.columns = {0, 0, std::min(w, tile_ceil(-dx, grid.ax)), h};
  if (dy > 0) uncovered_.rows = {0, std::max(0, tile_floor(h - dy, grid.ay)), w, h};
  if (dy < 0) uncovered_.rows = {0, 0, w, std::min(h, tile_ceil(-dy, grid.ay))};
  for (const TileRect& band : {uncovered_.columns, uncovered_.rows}) {
    if (band.x0 >= band.x1 || band.y0 >= band.y1) continue;
    for (int by = grid.row_of(band.y0); by <= grid.row_of(band.y1 - 1); ++by) {
      for (int bx = grid.column_of(band.x0); bx <= grid.column_of(band.x1 - 1); ++bx) {
        const std::size_t b = static_cast<std::size_t>(by) * static_cast<std::size_t>(grid.columns) + static_cast<std::size_t>(bx);
        if (mask_[b] == kBlockClean) mask_[b] = kBlockUncovered;
        if (layered_) layers_->drop_block(b);  // its layers lack the new tiles
      }
    }
  }
}

void ChangeTracker::mark_light(const PreparedScene& scene, const Footprint& f, const Aabb* region,
                               std::size_t light) {
  if (empty_box(f.influence)) return;
  const bool drop = region != nullptr && layered_;
  for (std::size_t b = 0; b < block_boxes_.size(); ++b) {
    if (mask_[b] == kBlockWhole && !drop) continue;
    const Aabb& box = block_boxes_[b];
    if (!f.takes_part(box, scene.model)) continue;
    if (region) {
      // The candidate query's hull lies in this box; a pixel to spare for rounding.
      Aabb reach_box = box_union(box, f.bounds);
      reach_box = {reach_box.min_x - pixel_, reach_box.min_y - pixel_, reach_box.max_x + pixel_, reach_box.max_y + pixel_};
      if (!boxes_meet(*region, reach_box)) continue;
    }
    mask_[b] = kBlockWhole;
    if (drop) layers_->drop(b, light);
  }
}

void ChangeTracker::plan_layer_fills(const PreparedScene& scene, bool full) {
  part_first_.assign(1, 0);
  part_lights_.clear();
  for (std::size_t b = 0; b < block_boxes_.size(); ++b) {
    if (full || mask_[b] == kBlockWhole) {
      for (std::size_t l = 0; l < old_.size(); ++l)
        if (old_[l].takes_part(block_boxes_[b], scene.model)) part_lights_.push_back(static_cast<std::uint32_t>(l));
    }
    part_first_.push_back(static_cast<std::uint32_t>(part_lights_.size()));
  }
  int planes = 1;
  for (const OccluderTerms& t : scene.occluder_terms)
    if (t.transmittance[0] != t.transmittance[1] || t.transmittance[0] != t.transmittance[2]) planes = 3;
  layers_->plan_frame(full ? nullptr : &mask_, part_first_, part_lights_, !scene.directionals.empty(), planes);
}

const std::vector<std::uint8_t>* ChangeTracker::plan(const PreparedScene& scene, const std::vector<LightReach>* reach,
                                                     const FrameKey& key, std::vector<PixelRect>& rects) {
  const std::size_t lights = scene.lights.size();
  const bool precise = reach != nullptr && reach->size() == lights && culling_trusted(scene) && !scene.bounce;
  bool full = full_ || !have_key_ || !(key == key_) || changed_.size() != lights;
  if (!full && any_ && !precise) full = true;
  if (!full && !regions_.empty() && !scene.directionals.empty()) full = true;
  // A move on the pixel grid: the buffer's pixels shift, and only the bands it uncovers are new.
  shift_x_ = shift_y_ = 0;
  uncovered_ = UncoveredPixels{};
  const std::int64_t move_x = key.grid_x - key_.grid_x, move_y = key.grid_y - key_.grid_y;
  if (!full && (move_x != 0 || move_y != 0)) {
    if (!key.scrolls || move_x <= -key.width || move_x >= key.width || move_y <= -key.height || move_y >= key.height) {
      full = true;
    } else {
      shift_x_ = static_cast<int>(move_x);
      shift_y_ = static_cast<int>(move_y);
    }
  }

  new_.assign(lights, Footprint{});
  // Pixel sizes of the grid (the same at every offset on it).
  pixel_ = std::max(std::abs(scene.view.x1 - scene.view.x0) / scene.width,
                    std::abs(scene.view.y1 - scene.view.y0) / scene.height);
  if (precise) {
    const double bw = std::abs(scene.view.x1 - scene.view.x0) / scene.width * kBlockSize;
    const double bh = std::abs(scene.view.y1 - scene.view.y0) / scene.height * kBlockSize;
    for (std::size_t l = 0; l < lights; ++l) {
      const LightReach& r = (*reach)[l];
      const PreparedLight& light = scene.lights[l];
      Footprint& f = new_[l];
      f.reach = r;
      f.bounds = bounds_of(light.shape);
      f.range = light.terms.range;
      // Not hidden: within max(farthest, radius) of the center (LightReach::hides).
      const double d = std::max(r.farthest, r.radius);
      Aabb in{r.center.x - d, r.center.y - d, r.center.x + d, r.center.y + d};
      if (scene.model && light.terms.has_range()) {  // not beyond_range: within range of the shape's box
        const double g = light.terms.range;
        in = intersection(in, {f.bounds.min_x - g, f.bounds.min_y - g, f.bounds.max_x + g, f.bounds.max_y + g});
      }
      f.influence = in;
      // Every block's hull with the light lies in Q_l.
      Aabb q = empty_box(in) ? kEmptyBox : Aabb{in.min_x - bw, in.min_y - bh, in.max_x + bw, in.max_y + bh};
      grow(q, f.bounds);
      f.query = {q.min_x - pixel_, q.min_y - pixel_, q.max_x + pixel_, q.max_y + pixel_};
    }
  }

  const BlockGrid grid = frame_blocks(scene);
  const int columns = grid.columns, rows = grid.rows;
  mask_.assign(grid.count(), full ? kBlockWhole : kBlockClean);
  // The layers: kept only where culling says which lights take part in which block.
  layered_ = layers_ != nullptr && layers_->budget() != 0 && precise;
  if (layers_ && (!layered_ || full)) layers_->clear();
  if (layered_ && (shift_x_ != 0 || shift_y_ != 0)) {
    // Block (bx, by) of the new grid is grid block floor(grid_x / kBlockSize) + bx.
    const auto block_of = [](std::int64_t p) { return (p >= 0 ? p : p - (kBlockSize - 1)) / kBlockSize; };
    layers_->move_blocks(BlockGrid(key_.width, key_.height, key_.grid_x, key_.grid_y), grid,
                         block_of(key.grid_x) - block_of(key_.grid_x), block_of(key.grid_y) - block_of(key_.grid_y));
  }
  if (layered_) layers_->set_block_count(mask_.size());
  if (!full && (shift_x_ != 0 || shift_y_ != 0)) plan_scroll(scene, shift_x_, shift_y_);
  if ((!full && any_) || layered_) {
    block_boxes_.resize(mask_.size());
    for (std::size_t b = 0; b < mask_.size(); ++b) block_boxes_[b] = bounds_of(tile_corners(scene, grid.block(b)));
  }
  if (!full && any_) {
    // A light changed, renumbered or with another reach: wherever it took part or takes part.
    for (std::size_t l = 0; l < lights; ++l) {
      const bool moved = (changed_[l] & kChanged) || !same_reach(old_[l].reach, new_[l].reach) ||
                         !same_box(old_[l].bounds, new_[l].bounds) || old_[l].range != new_[l].range;
      if (moved || changed_[l]) {
        mark_light(scene, old_[l], nullptr, l);
        mark_light(scene, new_[l], nullptr, l);
      }
      if (moved && layered_) layers_->drop_light(l);
    }
    if (layered_) layers_->drop_lights_from(lights);
    for (const Footprint& f : erased_) mark_light(scene, f, nullptr, 0);
    // An occluder changed in `r`: a candidate of light l in block B only if `r` meets the box
    // of B and the light, where l takes part in B.
    for (const Aabb& r : regions_) {
      mark(scene, r);  // an occluder holding a pixel
      for (std::size_t l = 0; l < lights; ++l) {
        if (boxes_meet(old_[l].query, r)) mark_light(scene, old_[l], &r, l);
        if (boxes_meet(new_[l].query, r)) mark_light(scene, new_[l], &r, l);
      }
    }
  }

  // This frame is now what the host's buffer holds.
  old_.swap(new_);
  if (layered_) plan_layer_fills(scene, full);
  changed_.assign(lights, 0);
  erased_.clear();
  regions_.clear();
  if (erased_.capacity() < kMaxRegions) erased_.reserve(kMaxRegions);
  if (regions_.capacity() < kMaxRegions) regions_.reserve(kMaxRegions);
  full_ = false;
  any_ = false;
  key_ = key;
  have_key_ = true;
  // The rectangles, disjoint: per block row, runs of blocks computed whole and the uncovered
  // part of each block a move uncovered (cut to the frame), each stacked on the rectangle of
  // the row above with the same columns where that one ends on its first row.
  rects.clear();
  for (int by = 0; by < rows; ++by) {
    const std::size_t first_of_row = rects.size();
    for (int bx = 0; bx < columns;) {
      const std::uint8_t mark = mask_[static_cast<std::size_t>(by * columns + bx)];
      TileRect piece{0, 0, 0, 0};
      int end = bx + 1;
      if (mark == kBlockWhole) {
        while (end < columns && mask_[static_cast<std::size_t>(by * columns + end)] == kBlockWhole) ++end;
        const TileRect first = grid.block(bx, by), last = grid.block(end - 1, by);
        piece = {first.x0, first.y0, last.x1, last.y1};
      } else if (mark == kBlockUncovered) {
        piece = uncovered_part(grid.block(bx, by), uncovered_);
      }
      bx = end;
      const PixelRect run{std::max(piece.x0, 0), std::max(piece.y0, 0), std::min(piece.x1, scene.width),
                          std::min(piece.y1, scene.height)};
      if (run.x0 >= run.x1 || run.y0 >= run.y1) continue;
      bool merged = false;
      for (std::size_t i = 0; i < first_of_row; ++i) {
        PixelRect& r = rects[i];
        if (r.x0 == run.x0 && r.x1 == run.x1 && r.y1 == run.y0) {
          r.y1 = run.y1;
          merged = true;
          break;
        }
      }
      if (!merged) rects.push_back(run);
    }
  }
  return full ? nullptr : &mask_;
}

}  // namespace par2d::detail
