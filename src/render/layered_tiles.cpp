// A tile through the light-layer cache: see layered_tiles.hpp.
#include "render/layered_tiles.hpp"

#include <algorithm>
#include <cstring>

namespace par2d::detail {
namespace {

// out += the layer's share of tile t times its light's emission, as build_tile_work hands
// emissions to the kernel (divided by 2 pi, in float).
void add_layer(const PreparedScene& scene, const LightLayer& layer, int t, const KernelSet& kernels,
               TileResult& out) noexcept {
  const Rgb& e = scene.lights[layer.light].emission;
  const float emission[3] = {static_cast<float>(e[0] / kTwoPi), static_cast<float>(e[1] / kTwoPi),
                             static_cast<float>(e[2] / kTwoPi)};
  kernels.add_light_layer(layer.data.data() + layer.offset[t], ((layer.mono >> t) & 1u) != 0, emission, out);
}

}  // namespace

void start_layered_block(std::size_t scene_lights, const std::vector<LightLayer>& layers, LayeredTileScratch& scratch) {
  scratch.layer_of.assign(scene_lights, -1);
  scratch.skip.assign(scene_lights, 0);
  for (std::size_t k = 0; k < layers.size(); ++k) {
    if (layers[k].light >= scene_lights) continue;
    scratch.layer_of[layers[k].light] = static_cast<std::int32_t>(k);
    scratch.skip[layers[k].light] = 1;
  }
}

void render_layered_tile(const PreparedScene& scene, const TileRect& tile, int t, const KernelSet& kernels,
                         bool fill, std::size_t layer_floats,
                         TileWork& work, const TileSetupScratch& setup, CellListScratch& cells,
                         std::vector<LightLayer>& layers, LayeredTileScratch& scratch, TileKernelRunner& runner,
                         TileResult& out, FrameCounters& counts) {
  // The tile's lights (scene lights first, in number order, then directional ones) move aside;
  // work.lights holds what each kernel call computes.
  scratch.all_lights.swap(work.lights);
  scratch.all_terms.swap(work.light_terms);
  const std::size_t count = scratch.all_lights.size();
  const std::size_t scene_lights = setup.tile_lights.size();
  const bool model = work.model;
  float ambient[3];
  std::copy(std::begin(work.ambient), std::end(work.ambient), ambient);
  scratch.rest.clear();
  // Lights with a layer were left out of the culling (`skip`): the work holds the others.
  for (std::size_t i = 0; i < count; ++i) {
    if (i >= scene_lights) {  // a directional light: no layer (it reaches every block)
      scratch.rest.push_back(static_cast<std::uint32_t>(i));
      continue;
    }
    const std::uint32_t l = setup.tile_lights[i];
    std::int32_t k = scratch.layer_of[l];
    if (!fill) {
      scratch.rest.push_back(static_cast<std::uint32_t>(i));
      continue;
    }
    if (k < 0) {
      k = static_cast<std::int32_t>(layers.size());
      layers.emplace_back();
      layers.back().clear(l);
      layers.back().data.reserve(layer_floats);
      scratch.layer_of[l] = k;
    }
    // The light alone at unit emission, without the ambient term: its share.
    work.lights.assign(1, scratch.all_lights[i]);
    std::fill(std::begin(work.lights[0].emission), std::end(work.lights[0].emission), 1.0f);
    work.light_terms.clear();
    if (model) work.light_terms.push_back(scratch.all_terms[i]);
    std::fill(std::begin(work.ambient), std::end(work.ambient), 0.0f);
    scratch.part_scene.assign(1, l);
    build_cell_lists(scene, tile, kernels.lanes, setup, work, cells, scratch.part_scene.data());
    runner.run(work, scratch.single);
    const float* const planes[3] = {scratch.single.rgb[0], scratch.single.rgb[1], scratch.single.rgb[2]};
    const bool mono = std::memcmp(planes[0], planes[1], sizeof(scratch.single.rgb[0])) == 0 &&
                      std::memcmp(planes[0], planes[2], sizeof(scratch.single.rgb[0])) == 0;
    layers[static_cast<std::size_t>(k)].store(t, planes, mono ? 1 : 3);
    ++counts.layer_tiles_filled;
  }

  // The rest with their own emissions, and the ambient term.
  std::copy(std::begin(ambient), std::end(ambient), work.ambient);
  if (!scratch.rest.empty()) {
    work.lights.clear();
    work.light_terms.clear();
    scratch.part_scene.clear();
    for (const std::uint32_t i : scratch.rest) {
      work.lights.push_back(scratch.all_lights[i]);
      if (model) work.light_terms.push_back(scratch.all_terms[i]);
      scratch.part_scene.push_back(i < scene_lights ? setup.tile_lights[i] : 0u);  // unread for directional lights
    }
    build_cell_lists(scene, tile, kernels.lanes, setup, work, cells, scratch.part_scene.data());
    runner.run(work, out);
  } else {
    for (int c = 0; c < 3; ++c) std::fill(std::begin(out.rgb[c]), std::end(out.rgb[c]), ambient[c]);
  }
  // The stored shares times their lights' emissions, in light order.
  for (std::size_t l = 0; l < scratch.layer_of.size(); ++l) {
    if (scratch.layer_of[l] < 0) continue;
    const LightLayer& layer = layers[static_cast<std::size_t>(scratch.layer_of[l])];
    if (layer.offset[t] < 0) continue;
    add_layer(scene, layer, t, kernels, out);
    counts.layer_tiles_reused += scratch.skip[l];
  }
  scratch.all_lights.swap(work.lights);
  scratch.all_terms.swap(work.light_terms);
}

void recombine_tile(const PreparedScene& scene, const std::vector<LightLayer>& layers, int t, const KernelSet& kernels,
                    TileResult& out, FrameCounters& counts) noexcept {
  for (std::size_t c = 0; c < 3; ++c) {
    const float ambient = scene.model ? static_cast<float>(scene.ambient[c]) : 0.0f;
    std::fill(std::begin(out.rgb[c]), std::end(out.rgb[c]), ambient);
  }
  for (const LightLayer& layer : layers) {
    if (layer.offset[t] < 0) continue;
    add_layer(scene, layer, t, kernels, out);
    ++counts.layer_tiles_reused;
  }
}

}  // namespace par2d::detail
