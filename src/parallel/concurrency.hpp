// How many workers the calling thread has, and whether the caller's-arena mode exists: both
// depend on whether par2d is built with TBB (PAR2D_HAVE_TBB, CMake's PAR2D_USE_TBB).
#pragma once

#if PAR2D_HAVE_TBB
#include <tbb/task_arena.h>
#endif

#include <algorithm>
#include <thread>

namespace par2d::detail {

// Threading::caller_arena runs in the TBB arena render is called from; a build without TBB has
// no such arena and refuses the mode (check_options).
#if PAR2D_HAVE_TBB
inline constexpr bool kCallerArena = true;
#else
inline constexpr bool kCallerArena = false;
#endif

// The concurrency of the calling thread's TBB arena (all hardware threads outside one); without
// TBB, the hardware threads.
inline int calling_concurrency() noexcept {
#if PAR2D_HAVE_TBB
  return tbb::this_task_arena::max_concurrency();
#else
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
#endif
}

}  // namespace par2d::detail
