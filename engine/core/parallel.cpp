#include "engine/core/parallel.h"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace cumulo {

unsigned worker_count() {
  if (const char* env = std::getenv("CUMULO_THREADS")) {
    int n = std::atoi(env);
    if (n > 0) return static_cast<unsigned>(n);
  }
  return std::max(1u, std::thread::hardware_concurrency());
}

void parallel_for(size_t count, const std::function<void(size_t, size_t)>& body, size_t min_chunk) {
  if (count == 0) return;
  unsigned workers = worker_count();
  // More chunks than workers so uneven work balances out.
  size_t chunk = std::max<size_t>(min_chunk, (count + workers * 8 - 1) / (workers * 8));
  if (workers == 1 || count <= chunk) {
    body(0, count);
    return;
  }
  std::atomic<size_t> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto run = [&] {
    for (;;) {
      size_t begin = next.fetch_add(chunk);
      if (begin >= count) return;
      try {
        body(begin, std::min(count, begin + chunk));
      } catch (...) {
        std::lock_guard lock(error_mutex);
        if (!error) error = std::current_exception();
        next = count;
      }
    }
  };
  std::vector<std::thread> threads;
  for (unsigned i = 1; i < workers; ++i) threads.emplace_back(run);
  run();
  for (auto& t : threads) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace cumulo
