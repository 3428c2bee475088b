// Scene to JSON: the inverse of parse_scene, for tools that edit scenes (the viewer, Python).
#pragma once

#include <string>

#include "par2d/scene.hpp"
#include "par2d/status.hpp"

// The public API is what the shared library exports (built with hidden visibility).
#pragma GCC visibility push(default)
namespace par2d {

// The scene as JSON in the format of docs/contract.md (section 3), one light or occluder per
// line. Numbers are written in their shortest form that reads back to the same double, so
// parse_scene(scene_to_json(s)) reproduces `s` exactly (colors and intensities included).
// The lighting model's terms (docs/contract.md section 6) are written only where they differ
// from their defaults. A normal map is written as its path (NormalMap::path, relative to the
// scene file's directory as when loaded), never embedded: the PNG must stay where the path
// points, and a map without a path is left out (save_scene_file refuses it).
// The scene is not validated: call validate_scene first if it may be invalid.
std::string scene_to_json(const Scene& scene);

// Validates the scene (messages prefixed with `path`), then writes scene_to_json to `path`
// atomically: a refused scene or a failed write leaves any existing file untouched.
Status save_scene_file(const std::string& path, const Scene& scene);

}  // namespace par2d
#pragma GCC visibility pop
