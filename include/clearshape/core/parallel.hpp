#pragma once
// Running n independent tasks on a few threads, with results by index and errors that do not
// depend on thread timing.
#include <cstddef>
#include <functional>

namespace clearshape {

/// Runs task(k) for k = 0 … n−1 on `threads` threads (the caller is one; ≤ 1 runs them in
/// order), each thread taking the next index. An exception stops the indices after it; every
/// index before it still runs, and the exception rethrown is the one of the lowest failing
/// index, so the same inputs give the same error whatever the thread count or timing.
/// `task` must write only to its own index's slot.
void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t)>& task);

}  // namespace clearshape
