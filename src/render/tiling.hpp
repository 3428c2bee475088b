// Image tiles (the kernel's unit) grouped in blocks (the unit of parallel work and of
// spatial-index queries).
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#if PAR2D_STD_THREADS
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>
#endif

#include "simd/tile_work.hpp"

namespace par2d::detail {

// Blocks of kBlockTiles x kBlockTiles tiles: one spatial-index query per block and light
// serves several tiles, and a 1920 x 1080 frame still has hundreds of blocks, so every
// one of 16 threads gets many (pbrt's rule of many small work items).
inline constexpr int kBlockTiles = 4;
inline constexpr int kBlockSize = kTileSize * kBlockTiles;

struct TileRect {
  int x0, y0, x1, y1;  // pixel columns [x0, x1), rows [y0, y1)
};

// Calls fn(rect) for the cells of `cell` pixels covering `area`, row by row.
template <class Fn>
void for_each_cell(const TileRect& area, int cell, Fn&& fn) {
  for (int y = area.y0; y < area.y1; y += cell) {
    for (int x = area.x0; x < area.x1; x += cell) fn(TileRect{x, y, std::min(x + cell, area.x1), std::min(y + cell, area.y1)});
  }
}

// Runs fn(index, worker) for every index in [0, count) on `threads` workers; `worker` in
// [0, threads) names the calling worker, so per-worker state can live in a plain array.
//
// The scheduler is TBB. Builds with PAR2D_STD_THREADS (the ThreadSanitizer build) use
// plain std::threads taking indices from an atomic counter instead: Debian's libtbb
// is not built with TSan, so TSan cannot see TBB's synchronization, while it sees
// std::thread's join. Everything the workers run is the same code either way.
template <class Fn>
void for_each_index(int count, int threads, Fn&& fn) {
#if PAR2D_STD_THREADS
  std::atomic<int> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto work = [&](int worker) {
    try {
      for (int i = next.fetch_add(1); i < count; i = next.fetch_add(1)) fn(i, worker);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(failure_mutex);
      if (!failure) failure = std::current_exception();
      next.store(count);
    }
  };
  std::vector<std::thread> pool;
  for (int w = 1; w < threads; ++w) pool.emplace_back(work, w);
  work(0);
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
#else
  tbb::task_arena arena(threads);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, count, 1), [&](const tbb::blocked_range<int>& range) {
      const int worker = tbb::this_task_arena::current_thread_index();
      for (int i = range.begin(); i != range.end(); ++i) fn(i, worker);
    });
  });
#endif
}

// Runs fn(block_rect, worker) for every block of the width x height image (see
// for_each_index). Iterates block indices, not pixel ranges (blocked_range splits at
// midpoints, which would not stay aligned to tiles and SIMD packets). Each block writes
// only its own pixels, so the image does not depend on the thread count.
template <class Fn>
void for_each_block(int width, int height, int threads, Fn&& fn) {
  const int columns = (width + kBlockSize - 1) / kBlockSize;
  const int rows = (height + kBlockSize - 1) / kBlockSize;
  for_each_index(columns * rows, threads, [&](int b, int worker) {
    const int x0 = (b % columns) * kBlockSize, y0 = (b / columns) * kBlockSize;
    fn(TileRect{x0, y0, std::min(x0 + kBlockSize, width), std::min(y0 + kBlockSize, height)}, worker);
  });
}

}  // namespace par2d::detail
