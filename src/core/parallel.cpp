// parallel_for (core/parallel.hpp): a shared index counter and the lowest failing index.
#include "clearshape/core/parallel.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace clearshape {

void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t)>& task) {
  std::atomic<std::size_t> next{0};
  std::mutex error_mutex;
  std::exception_ptr error;
  std::size_t error_at = n;  // the lowest failing index so far
  const auto worker = [&] {
    for (std::size_t k = next.fetch_add(1); k < n; k = next.fetch_add(1)) {
      {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (error_at < k) return;  // indices before a failure still run: one of them may fail first
      }
      try {
        task(k);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (k < error_at) {
          error = std::current_exception();
          error_at = k;
        }
      }
    }
  };
  const auto count = static_cast<std::size_t>(std::max(1, threads));
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < std::min(count, n); ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace clearshape
