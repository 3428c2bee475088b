// Scene to JSON text and to files (the inverse of scene_json.cpp's loader).
#include "par2d/scene_write.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <variant>

#include <nlohmann/json.hpp>

#include "io/file_compat.hpp"
#include "scene/shortest_double.hpp"

namespace par2d {
namespace {

// Shortest decimal that reads back as the same double (std::to_chars without a precision),
// so a written scene loads bit-identical and integers stay integers ("512", not "512.0").
void put_number(std::string& out, double v) {
  out += detail::shortest_double(v);
}

void put_point(std::string& out, const Vec2& p) {
  out += '[';
  put_number(out, p.x);
  out += ", ";
  put_number(out, p.y);
  out += ']';
}

void put_shape(std::string& out, const Shape& shape) {
  std::visit(
      [&out](const auto& s) {
        using T = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<T, Polygon>) {
          const auto put_ring = [&out](const std::vector<Vec2>& ring) {
            out += '[';
            for (std::size_t i = 0; i < ring.size(); ++i) {
              if (i > 0) out += ", ";
              put_point(out, ring[i]);
            }
            out += ']';
          };
          out += "\"polygon\": ";
          put_ring(s.vertices);
          if (!s.holes.empty()) {
            out += ", \"holes\": [";
            for (std::size_t k = 0; k < s.holes.size(); ++k) {
              if (k > 0) out += ", ";
              put_ring(s.holes[k]);
            }
            out += ']';
          }
        } else if constexpr (std::is_same_v<T, Circle>) {
          out += "\"circle\": { \"center\": ";
          put_point(out, s.center);
          out += ", \"radius\": ";
          put_number(out, s.radius);
          out += " }";
        } else {
          out += "\"segment\": [";
          put_point(out, s.a);
          out += ", ";
          put_point(out, s.b);
          out += ']';
        }
      },
      shape);
}

void put_triple(std::string& out, const double* v) {
  out += '[';
  for (int c = 0; c < 3; ++c) {
    if (c > 0) out += ", ";
    put_number(out, v[c]);
  }
  out += ']';
}

// Only terms that differ from their defaults are written, so plain scenes stay as they were.
void put_mask(std::string& out, std::uint32_t mask) {
  if (mask == kAllMaskBits) return;
  out += ", \"mask\": " + std::to_string(mask);
}

void put_elevation(std::string& out, double elevation) {
  if (elevation == 0.0 && !std::signbit(elevation)) return;
  out += ", \"elevation\": ";
  put_number(out, elevation);
}

void put_light_terms(std::string& out, const Light& light) {
  if (light.range) {
    out += ", \"range\": ";
    put_number(out, *light.range);
  }
  if (light.normalize) {
    out += ", \"normalize\": ";
    put_number(out, *light.normalize);
  }
  if (light.falloff != 2.0) {
    out += ", \"falloff\": ";
    put_number(out, light.falloff);
  }
  if (light.cone) {
    out += ", \"cone\": { \"direction\": ";
    put_number(out, light.cone->direction);
    out += ", \"half_angle\": ";
    put_number(out, light.cone->half_angle);
    out += ", \"fade\": ";
    put_number(out, light.cone->fade);
    out += " }";
  }
  if (light.cookie) {
    out += ", \"cookie\": { \"rotation\": ";
    put_number(out, light.cookie->rotation);
    out += ", \"knots\": [";
    for (std::size_t k = 0; k < light.cookie->knots.size(); ++k) {
      out += k == 0 ? "[" : ", [";
      put_number(out, light.cookie->knots[k].direction);
      out += ", ";
      put_number(out, light.cookie->knots[k].weight);
      out += "]";
    }
    out += "] }";
  }
  put_mask(out, light.mask);
  put_elevation(out, light.elevation);
  // The default (full shadows) is left out; -0 is written, so a round trip keeps every bit.
  const Shadow full;
  if (std::memcmp(&light.shadow.strength, &full.strength, sizeof(double)) != 0 ||
      std::memcmp(light.shadow.color.data(), full.color.data(), sizeof(Rgb)) != 0) {
    out += ", \"shadow\": { \"strength\": ";
    put_number(out, light.shadow.strength);
    out += ", \"color\": ";
    put_triple(out, light.shadow.color.data());
    out += " }";
  }
}

void put_occluder_terms(std::string& out, const Occluder& occluder) {
  const Rgb& t = occluder.transmittance;
  if (std::signbit(t[0]) || std::signbit(t[1]) || std::signbit(t[2]) || t[0] != 0.0 || t[1] != 0.0 || t[2] != 0.0) {
    out += ", \"transmittance\": ";
    put_triple(out, t.data());
  }
  put_mask(out, occluder.mask);
  if (occluder.interior == Interior::lit) out += ", \"interior\": \"lit\"";
  const Rgb& a = occluder.albedo;
  if (std::signbit(a[0]) || std::signbit(a[1]) || std::signbit(a[2]) || a[0] != 0.0 || a[1] != 0.0 || a[2] != 0.0) {
    out += ", \"albedo\": ";
    put_triple(out, a.data());
  }
}

// The scene-wide terms, each on its own line after the occluders.
void put_scene_terms(std::string& out, const Scene& scene) {
  const Rgb& a = scene.ambient;
  if (std::signbit(a[0]) || std::signbit(a[1]) || std::signbit(a[2]) || a[0] != 0.0 || a[1] != 0.0 || a[2] != 0.0) {
    out += ",\n  \"ambient\": ";
    put_triple(out, a.data());
  }
  if (!scene.directional_lights.empty()) {
    out += ",\n  \"directional_lights\": [";
    for (std::size_t i = 0; i < scene.directional_lights.size(); ++i) {
      const DirectionalLight& d = scene.directional_lights[i];
      out += i > 0 ? ",\n    { \"angles\": [" : "\n    { \"angles\": [";
      put_number(out, d.angle0);
      out += ", ";
      put_number(out, d.angle1);
      out += "], \"color\": ";
      put_triple(out, d.color.data());
      out += ", \"intensity\": ";
      put_number(out, d.intensity);
      put_mask(out, d.mask);
      put_elevation(out, d.elevation);
      out += " }";
    }
    out += "\n  ]";
  }
  if (scene.normal) {
    const double n[3] = {scene.normal->x, scene.normal->y, scene.normal->z};
    out += ",\n  \"normal\": ";
    put_triple(out, n);
  }
  // The map is named, not embedded: its PNG stays where the path (relative to the scene
  // file's directory) points. A map built in code without a path cannot be named.
  if (scene.normal_map && !scene.normal_map->path.empty()) {
    out += ",\n  \"normal_map\": ";
    out += nlohmann::json(scene.normal_map->path).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  }
  if (scene.bounce.piece != Bounce{}.piece || scene.bounce.step != Bounce{}.step) {
    out += ",\n  \"bounce\": { \"piece\": ";
    put_number(out, scene.bounce.piece);
    out += ", \"step\": " + std::to_string(scene.bounce.step) + " }";
  }
}

std::string errno_text(const std::string& path, const char* what, int err) {
  return path + ": " + what + ": " + std::strerror(err);
}

}  // namespace

std::string scene_to_json(const Scene& scene) {
  std::string out = "{\n  \"width\": " + std::to_string(scene.width) +
                    ", \"height\": " + std::to_string(scene.height) + ",\n  \"view\": [";
  const double view[4] = {scene.view.x0, scene.view.y0, scene.view.x1, scene.view.y1};
  for (int i = 0; i < 4; ++i) {
    if (i > 0) out += ", ";
    put_number(out, view[i]);
  }
  out += "],\n  \"lights\": [";
  for (std::size_t i = 0; i < scene.lights.size(); ++i) {
    const Light& light = scene.lights[i];
    out += i > 0 ? ",\n    { " : "\n    { ";
    put_shape(out, light.shape);
    out += ", \"color\": [";
    for (int c = 0; c < 3; ++c) {
      if (c > 0) out += ", ";
      put_number(out, light.color[static_cast<std::size_t>(c)]);
    }
    out += "], \"intensity\": ";
    put_number(out, light.intensity);
    put_light_terms(out, light);
    out += " }";
  }
  out += scene.lights.empty() ? "],\n  \"occluders\": [" : "\n  ],\n  \"occluders\": [";
  for (std::size_t i = 0; i < scene.occluders.size(); ++i) {
    out += i > 0 ? ",\n    { " : "\n    { ";
    put_shape(out, scene.occluders[i].shape);
    put_occluder_terms(out, scene.occluders[i]);
    out += " }";
  }
  out += scene.occluders.empty() ? "]" : "\n  ]";
  put_scene_terms(out, scene);
  out += "\n}\n";
  return out;
}

Status save_scene_file(const std::string& path, const Scene& scene) {
  if (Status status = validate_scene(scene, path); !status) return status;
  if (scene.normal_map && scene.normal_map->path.empty()) {
    return {StatusCode::invalid_argument,
            path + ": normal_map: has no path (a scene file names its normal map's PNG; set NormalMap::path)"};
  }
  const std::string text = scene_to_json(scene);
  // Written to a sibling and renamed (atomic on POSIX), so an editor or the viewer's file
  // watch never sees half a scene, and a failed write leaves the old file as it was.
  const std::string temp = path + ".tmp" + std::to_string(::getpid());
  int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | detail::kOpenFlags, 0666);
  if (fd < 0) return {StatusCode::io_error, errno_text(path, "cannot create", errno)};
  const char* bytes = text.data();
  std::size_t left = text.size();
  while (left > 0) {
    const auto n = ::write(fd, bytes, static_cast<unsigned>(std::min<std::size_t>(left, std::size_t{1} << 30)));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      int err = errno;
      ::close(fd);
      ::unlink(temp.c_str());
      return {StatusCode::io_error, errno_text(path, "write failed", err)};
    }
    bytes += n;
    left -= static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0 || detail::replace_file(temp, path) != 0) {
    int err = errno;
    ::unlink(temp.c_str());
    return {StatusCode::io_error, errno_text(path, "cannot write", err)};
  }
  return {};
}

}  // namespace par2d
