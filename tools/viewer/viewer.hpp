// `par2d view SCENE.json`: a window showing the lit scene live, for moving, resizing, adding and deleting lights.
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace par2d::viewer {

struct ViewArgs {
  std::string scene_path;
  // Where the save key writes the edited scene (the scene file only when named here). Default:
  // SCENE.edited.json next to the scene, or SCENE.edited-N.json, the first that does not exist.
  std::string save_path;
  // Where the save key writes the rendered image (the scene at its own size, as
  // `par2d render -o` writes it). Default: SCENE.screenshot.png next to the scene.
  // The window itself, heads-up text included, goes to the same name ending .window.png.
  std::string screenshot_path;
  std::string backend = "auto";
  std::string isa;  // empty: PAR2D_ISA or the best the CPU has
  int threads = 0;
  double exposure = 1.0;
};

// Adds the `view` subcommand and its options to `app`; returns it.
CLI::App* add_view_command(CLI::App& app, ViewArgs& args);

// Runs the viewer until the window closes. Returns the process exit status; errors that
// stop it (no display, unreadable scene) are one line on stderr.
int run_view(const ViewArgs& args);

}  // namespace par2d::viewer
