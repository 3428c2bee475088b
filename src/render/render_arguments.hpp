// Argument checks shared by the one-shot render, the ray-casting baseline and par2d::Renderer
// (one wording for all), and the worker count they resolve (render_arguments.cpp).
#pragma once

#include "par2d/render.hpp"
#include "par2d/status.hpp"
#include "par2d/types.hpp"

namespace par2d::detail {

// Workers for `requested` threads: 0 means the calling thread's concurrency (TBB's, or the
// hardware threads in a build without TBB: parallel/concurrency.hpp); more
// than the hardware threads are capped there.
int worker_threads(int requested) noexcept;

// threads >= 0, spp and rays in range, known backend, ISA and threading. `who` prefixes messages.
Status check_options(const RenderOptions& options, const char* who);
// check_options and the rays of the ray caster (render_raycast).
Status check_raycast_options(const RenderOptions& options, const char* who);

// Non-null data, known format, finite exposure >= 0, a non-empty region inside the
// width x height frame, and a row stride that holds a row of the region.
Status check_frame_buffer(const FrameBuffer& buffer, const PixelRect& region, int width, int height, const char* who);

// Non-null data, the width x height size (`what` names whose size: "scene", "frame"), and a
// row stride that holds a row.
Status check_image_view(const ImageView& image, int width, int height, const char* who, const char* what);

// The float RGB image as the frame buffer it is.
inline FrameBuffer frame_buffer_of(const ImageView& image) noexcept {
  FrameBuffer buffer;
  buffer.data = image.data;
  buffer.format = PixelFormat::rgb_f32;
  buffer.row_stride = image.row_stride * static_cast<std::ptrdiff_t>(sizeof(float));
  return buffer;
}

}  // namespace par2d::detail
