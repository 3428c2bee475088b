// Where a frame's parallel work runs: a persistent TBB arena owned by the renderer, or the
// arena the host called from. Made once (Renderer::set_options), never per frame. Builds with
// PAR2D_STD_THREADS run the same indices on std::threads (parallel_for.hpp) instead.
#pragma once

#if !PAR2D_STD_THREADS
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#endif

#include <memory>

#include "par2d/types.hpp"
#include "parallel/concurrency.hpp"
#include "parallel/parallel_for.hpp"

namespace par2d::detail {

class Scheduler {
 public:
  // `threads` >= 1 workers in an arena of our own, or the caller's arena.
  void configure(int threads, Threading threading) {
    threading_ = threading;
    threads_ = threads;
#if !PAR2D_STD_THREADS
    arena_.reset();
    if (threading == Threading::own_pool) {
      arena_ = std::make_unique<tbb::task_arena>(threads);
      arena_->initialize();  // its threads start now, not on the first frame
    }
#endif
  }

  bool configured() const noexcept { return threads_ > 0; }

  // The number of distinct worker indices for_each_index may pass from this thread.
  int workers() const noexcept {
    if (threading_ == Threading::caller_arena) return calling_concurrency();
    return threads_;
  }

  // fn(index, worker) for every index in [0, count), worker in [0, workers()).
  template <class Fn>
  void for_each_index(int count, Fn&& fn) const {
#if PAR2D_STD_THREADS
    detail::for_each_index(count, workers(), fn);
#else
    auto body = [&] {
      tbb::parallel_for(tbb::blocked_range<int>(0, count, 1), [&](const tbb::blocked_range<int>& range) {
        const int worker = tbb::this_task_arena::current_thread_index();
        for (int i = range.begin(); i != range.end(); ++i) fn(i, worker);
      });
    };
    if (count <= 0) return;
    if (arena_) {
      arena_->execute(body);
    } else {
      body();
    }
#endif
  }

 private:
  Threading threading_ = Threading::own_pool;
  int threads_ = 0;
#if !PAR2D_STD_THREADS
  std::unique_ptr<tbb::task_arena> arena_;
#endif
};

}  // namespace par2d::detail
