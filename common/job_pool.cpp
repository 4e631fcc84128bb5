#include "common/job_pool.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace shapepress {

void run_jobs(std::size_t count, int workers, const std::function<void(std::size_t)>& job) {
  const std::size_t team =
      std::min<std::size_t>(static_cast<std::size_t>(std::max(workers, 1)), count);
  if (team <= 1) {
    for (std::size_t i = 0; i < count; ++i)
      job(i);
    return;
  }
  std::atomic<std::size_t> next{0};
  std::mutex lock;
  std::exception_ptr failure;
  const auto stop = [&](std::exception_ptr e) {
    const std::lock_guard guard(lock);
    if (!failure) failure = std::move(e);
    next = count;  // the jobs not started are skipped
  };
  const auto worker = [&] {
    for (std::size_t i = next++; i < count; i = next++) {
      try {
        job(i);
      } catch (...) {
        stop(std::current_exception());
      }
    }
  };
  std::vector<std::thread> threads;
  threads.reserve(team);
  try {
    for (std::size_t t = 0; t < team; ++t)
      threads.emplace_back(worker);
  } catch (...) {  // a thread the system would not start: the started ones finish what they took
    stop(std::current_exception());
  }
  for (std::thread& t : threads)
    t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace shapepress
