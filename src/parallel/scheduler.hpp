// Where a frame's parallel work runs: a persistent TBB arena owned by the renderer, or the
// arena the host called from. Made once (Renderer::set_options), never per frame. Builds with
// PAR2D_STD_THREADS run the same indices on std::threads (parallel_for.hpp) instead.
#pragma once

#if !PAR2D_STD_THREADS
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <mutex>
#include <utility>
#include <vector>
#endif

#include <memory>

#include "par2d/types.hpp"
#include "parallel/concurrency.hpp"
#include "parallel/parallel_for.hpp"

namespace par2d::detail {

#if !PAR2D_STD_THREADS
// The arenas of schedulers that are gone, kept for the next scheduler of the same thread
// count. A one-shot render (par2d::render) makes a Renderer, so a scheduler, per frame; TBB's
// worker threads often do not join an arena made just after another was destroyed, leaving
// the frame to the calling thread alone, while a kept arena gets its workers every frame
// (docs/performance.md, "Threads"). An arena serves one scheduler at a time, as when each
// made its own. At most kMaxIdle are kept; the pool is never destroyed (its arenas would
// otherwise end during static destruction, after TBB's own state may be gone).
class IdleArenas {
 public:
  static std::unique_ptr<tbb::task_arena> take(int threads) {
    IdleArenas& pool = instance();
    {
      const std::lock_guard<std::mutex> lock(pool.mutex_);
      for (auto it = pool.arenas_.begin(); it != pool.arenas_.end(); ++it) {
        if (it->first != threads) continue;
        std::unique_ptr<tbb::task_arena> arena = std::move(it->second);
        pool.arenas_.erase(it);
        return arena;
      }
    }
    auto arena = std::make_unique<tbb::task_arena>(threads);
    arena->initialize();  // its threads start now, not on the first frame
    return arena;
  }
  static void give(int threads, std::unique_ptr<tbb::task_arena> arena) {
    if (!arena) return;
    IdleArenas& pool = instance();
    const std::lock_guard<std::mutex> lock(pool.mutex_);
    if (pool.arenas_.size() < kMaxIdle) pool.arenas_.emplace_back(threads, std::move(arena));
    // else the arena ends with the argument, once the lock is released
  }

 private:
  static constexpr std::size_t kMaxIdle = 8;
  static IdleArenas& instance() {
    static IdleArenas* pool = new IdleArenas;
    return *pool;
  }
  std::mutex mutex_;
  std::vector<std::pair<int, std::unique_ptr<tbb::task_arena>>> arenas_;
};
#endif

class Scheduler {
 public:
  Scheduler() = default;
  Scheduler(const Scheduler&) = delete;
  Scheduler& operator=(const Scheduler&) = delete;
  ~Scheduler() { release(); }

  // `threads` >= 1 workers in an arena of our own (taken from the idle ones when one of that
  // count is there), or the caller's arena.
  void configure(int threads, Threading threading) {
#if !PAR2D_STD_THREADS
    release();
    if (threading == Threading::own_pool) arena_ = IdleArenas::take(threads);
#endif
    threading_ = threading;
    threads_ = threads;
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
  // Hands the arena (if any) back to the idle ones.
  void release() noexcept {
#if !PAR2D_STD_THREADS
    if (!arena_) return;
    try {
      IdleArenas::give(threads_, std::move(arena_));
    } catch (...) {  // no room to keep it: it ends with the pointer
    }
    arena_.reset();
#endif
  }

  Threading threading_ = Threading::own_pool;
  int threads_ = 0;
#if !PAR2D_STD_THREADS
  std::unique_ptr<tbb::task_arena> arena_;
#endif
};

}  // namespace par2d::detail
