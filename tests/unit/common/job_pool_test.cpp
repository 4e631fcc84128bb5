// The job pool runs every job once whatever the workers, never more at a time than it was given
// (and as many as it was given, when the jobs wait for each other), on the calling thread with
// one worker, and rethrows a job's exception after the running jobs end, skipping the rest.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <numeric>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "common/job_pool.hpp"

namespace shapepress {
namespace {

using namespace std::chrono_literals;

// How many jobs run at once: each holds its place a moment so the others can start.
class Concurrency {
 public:
  void enter() {
    const int now = ++running_;
    int seen = peak_.load();
    while (now > seen && !peak_.compare_exchange_weak(seen, now)) {
    }
    std::this_thread::sleep_for(5ms);
    --running_;
  }
  int peak() const { return peak_.load(); }

 private:
  std::atomic<int> running_{0};
  std::atomic<int> peak_{0};
};

TEST(JobPool, EveryJobRunsOnceAndTheResultsDoNotDependOnTheWorkers) {
  constexpr std::size_t count = 200;
  const auto squares = [](int workers) {
    std::vector<std::atomic<int>> calls(count);
    std::vector<long> result(count, -1);
    run_jobs(count, workers, [&](std::size_t i) {
      ++calls[i];
      // Uneven work, so the workers take the indices in an order of their own.
      if (i % 7 == 0) std::this_thread::sleep_for(1ms);
      result[i] = static_cast<long>(i * i);
    });
    for (std::size_t i = 0; i < count; ++i)
      EXPECT_EQ(calls[i].load(), 1) << "job " << i << " on " << workers << " workers";
    return result;
  };
  const std::vector<long> one = squares(1);
  EXPECT_EQ(std::accumulate(one.begin(), one.end(), 0L), 199L * 200L * 399L / 6L);
  EXPECT_EQ(squares(2), one);
  EXPECT_EQ(squares(5), one);
  EXPECT_EQ(squares(500), one);  // more workers than jobs
}

TEST(JobPool, NoJobsCallNothing) {
  bool called = false;
  run_jobs(0, 4, [&](std::size_t) { called = true; });
  EXPECT_FALSE(called);
}

TEST(JobPool, OneWorkerRunsTheJobsInOrderOnTheCallingThread) {
  for (int workers : {1, 0, -3}) {  // fewer than one counts as one
    std::vector<std::size_t> order;
    std::vector<std::thread::id> threads;
    run_jobs(6, workers, [&](std::size_t i) {
      order.push_back(i);
      threads.push_back(std::this_thread::get_id());
    });
    EXPECT_EQ(order, (std::vector<std::size_t>{0, 1, 2, 3, 4, 5}));
    for (const std::thread::id& id : threads)
      EXPECT_EQ(id, std::this_thread::get_id());
  }
}

TEST(JobPool, NeverMoreJobsAtOnceThanWorkers) {
  for (int workers : {1, 2, 3}) {
    Concurrency c;
    run_jobs(24, workers, [&](std::size_t) { c.enter(); });
    EXPECT_LE(c.peak(), workers);
    EXPECT_GE(c.peak(), 1);
  }
}

TEST(JobPool, TheWorkersAskedForRunSideBySideBeyondTheCores) {
  // Eight jobs that each wait until all eight have started: they end only if eight workers run
  // at once, however many cores the machine has (advise's workers wait on child processes).
  constexpr int workers = 8;
  std::mutex lock;
  std::condition_variable all_in;
  int started = 0;
  bool met = true;
  run_jobs(workers, workers, [&](std::size_t) {
    std::unique_lock guard(lock);
    ++started;
    all_in.notify_all();
    if (!all_in.wait_for(guard, 10s, [&] { return started == workers; })) met = false;
  });
  EXPECT_TRUE(met) << started << " of " << workers << " jobs ran at once";
}

TEST(JobPool, TheFirstExceptionIsRethrownAfterTheRunningJobsEndAndTheRestAreSkipped) {
  // Job 1 fails while jobs 0 and 2 run; those two end (they wait for the failure, then a
  // moment) before the exception reaches the caller, and no job is started after it.
  constexpr std::size_t count = 100;
  std::atomic<int> started{0}, finished{0};
  std::atomic<bool> failed{false};
  int started_at_throw = -1, finished_at_throw = -1;
  try {
    run_jobs(count, 3, [&](std::size_t i) {
      ++started;
      if (i == 1) {
        failed = true;
        throw std::runtime_error("job 1 failed");
      }
      const auto give_up = std::chrono::steady_clock::now() + 10s;
      while (!failed && std::chrono::steady_clock::now() < give_up)
        std::this_thread::sleep_for(1ms);
      std::this_thread::sleep_for(20ms);
      ++finished;
    });
    FAIL() << "run_jobs did not rethrow";
  } catch (const std::runtime_error& e) {
    started_at_throw = started.load();
    finished_at_throw = finished.load();
    EXPECT_STREQ(e.what(), "job 1 failed");
  }
  EXPECT_EQ(finished_at_throw, started_at_throw - 1);  // all but the failed one ended
  EXPECT_GE(started_at_throw, 2);
  EXPECT_LT(started_at_throw, static_cast<int>(count) / 2);  // the rest were skipped
  std::this_thread::sleep_for(50ms);
  EXPECT_EQ(started.load(), started_at_throw);  // and none started later
}

TEST(JobPool, OfSeveralFailuresOneIsRethrownOnce) {
  int caught = 0;
  try {
    run_jobs(4, 4, [](std::size_t i) { throw std::out_of_range("job " + std::to_string(i)); });
  } catch (const std::out_of_range& e) {
    ++caught;
    EXPECT_EQ(std::string(e.what()).rfind("job ", 0), 0u) << e.what();
  }
  EXPECT_EQ(caught, 1);
}

TEST(JobPool, OnOneWorkerAFailureEndsTheJobsThere) {
  std::vector<std::size_t> ran;
  EXPECT_THROW(run_jobs(5, 1,
                        [&](std::size_t i) {
                          ran.push_back(i);
                          if (i == 2) throw std::invalid_argument("job 2");
                        }),
               std::invalid_argument);
  EXPECT_EQ(ran, (std::vector<std::size_t>{0, 1, 2}));
}

}  // namespace
}  // namespace shapepress
