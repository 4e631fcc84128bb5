#pragma once
// The one job pool: the runs a stage makes side by side (advise's child processes, a
// calibration's trial compactions, an ensemble's fills) go through run_jobs.
#include <cstddef>
#include <functional>

namespace shapepress {

// Calls job(i) once for every i in [0, count), at most `workers` at a time (fewer than 1 counts
// as 1), each worker taking the next index as it finishes one: the order jobs start and end in is
// not fixed, so a job writes its result into slot i and the caller reads the slots in order.
//
// With one worker (or one job) the jobs run on the calling thread, in index order. With more,
// each worker is a thread of its own started for this call and joined before it returns, while
// the caller waits: per-thread state a job sets (OpenMP's thread count for an engine inside it)
// ends with its worker and never reaches the caller or another call's jobs. The jobs are meant
// to be long (an engine run, a child process); the workers are not capped at the cores, so a
// caller asking for more runs more.
//
// The first exception a job throws stops the jobs not yet started; once the running ones have
// finished, it is rethrown (a later one is dropped).
void run_jobs(std::size_t count, int workers, const std::function<void(std::size_t)>& job);

}  // namespace shapepress
