#include "support/bounce_scenes.hpp"

#include <utility>

namespace par2d::test {

Occluder reflector(Shape shape, Rgb albedo) {
  Occluder o;
  o.shape = std::move(shape);
  o.albedo = albedo;
  return o;
}

Scene bounce_mixed_scene() {
  Scene s;
  s.width = 32;
  s.height = 24;
  s.view = {-80, -60, 80, 60};
  Light a;
  a.shape = Circle{{-30, -35}, 5};
  a.intensity = 2;
  a.color = {1, 0.8, 0.6};
  s.lights.push_back(a);
  Light b;
  b.shape = Segment{{40, -50}, {60, -40}};
  b.color = {0.3, 0.6, 1};
  s.lights.push_back(b);
  s.occluders.push_back(reflector(Polygon{{{-50, 10}, {-10, 10}, {10, 10}, {10, 25}, {-50, 25}}}, {0.9, 0.6, 0.3}));
  s.occluders.push_back(reflector(Circle{{30, 5}, 9}, {0.2, 0.8, 0.4}));
  s.occluders.push_back(reflector(Segment{{-60, -20}, {-45, 0}}, {1, 1, 1}));
  Occluder glass;
  glass.shape = Circle{{0, -15}, 6};
  glass.transmittance = {0.6, 0.3, 0.9};
  s.occluders.push_back(glass);
  Occluder block;
  block.shape = Polygon{{{50, 20}, {65, 20}, {65, 35}}};
  s.occluders.push_back(block);
  s.bounce.piece = 7;
  return s;
}

}  // namespace par2d::test
