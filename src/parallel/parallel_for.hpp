// The one parallel loop of the library: every frame's blocks, the ray caster's rows and the
// lights' reach proofs run through for_each_index (directly, or through a Scheduler's arena).
#pragma once

#if PAR2D_STD_THREADS
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>
#else
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#endif

namespace par2d::detail {

// Runs fn(index, worker) for every index in [0, count) on `threads` workers; `worker` in
// [0, threads) names the calling worker, so per-worker state can live in a plain array.
//
// The scheduler is TBB. Builds with PAR2D_STD_THREADS (builds without TBB, and the
// ThreadSanitizer build) use plain std::threads taking indices from an atomic counter instead:
// Debian's libtbb is not built with TSan, so TSan cannot see TBB's synchronization, while it
// sees std::thread's join. Everything the workers run is the same code either way, and each
// index's result depends on its index alone, so the bytes are the same.
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

}  // namespace par2d::detail
