// `par2d outline`: occluders traced from a sprite PNG's alpha, written as a scene file.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "par2d/alpha_outline.hpp"
#include "par2d/status.hpp"

namespace par2d::cli {

struct OutlineArgs {
  std::string png_path;
  std::string output_path;
  par2d::AlphaOutlineOptions options;
};

// Adds the `outline` subcommand to `app`, its options bound to `args`.
CLI::App* add_outline_command(CLI::App& app, OutlineArgs& args);

// Loads the PNG, traces it and writes the scene (all or nothing; "-": standard output, refused
// where `stdout_closed`, as the process started with descriptor 1 closed). A failure's message
// names the file and the place.
par2d::Status run_outline(const OutlineArgs& args, bool stdout_closed);

}  // namespace par2d::cli
