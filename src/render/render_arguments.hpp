// Argument checks shared by the one-shot render and par2d::Renderer (one wording for both).
#pragma once

#include "par2d/render.hpp"
#include "par2d/renderer.hpp"
#include "par2d/status.hpp"

namespace par2d::detail {

// threads >= 0, spp and rays in range, known backend, ISA and threading. `who` prefixes messages.
Status check_options(const RenderOptions& options, const char* who);

// Non-null data, known format, finite exposure >= 0, a non-empty region inside the
// width x height frame, and a row stride that holds a row of the region.
Status check_frame_buffer(const FrameBuffer& buffer, const PixelRect& region, int width, int height, const char* who);

}  // namespace par2d::detail
