// Runs independent iterations of a loop on all cores.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace facerig {

// Calls body(state, i) for every i in [0, count), chunks of `chunk` indices
// handed to the next free thread (the calling thread is one of them; at most
// max_threads, 0: one per core). Each thread has its own default-constructed
// State (scratch space). Each iteration must write only its own outputs, so
// the result does not depend on the split. The first exception (in thread
// order) is rethrown on the caller.
template <class State, class Body>
void ParallelForWithState(std::size_t count, std::size_t chunk, std::size_t max_threads, const Body& body) {
  chunk = std::max<std::size_t>(chunk, 1);
  const std::size_t chunks = (count + chunk - 1) / chunk;
  const std::size_t cores = max_threads > 0 ? max_threads : std::max(1u, std::thread::hardware_concurrency());
  const std::size_t threads = std::min<std::size_t>(cores, std::max<std::size_t>(chunks, 1));
  std::vector<std::exception_ptr> failures(threads);
  std::atomic<std::size_t> next{0};
  auto run = [&](std::size_t t) {
    try {
      State state;
      for (std::size_t c = next++; c < chunks; c = next++) {
        const std::size_t end = std::min(count, (c + 1) * chunk);
        for (std::size_t i = c * chunk; i < end; ++i) body(state, i);
      }
    } catch (...) {
      failures[t] = std::current_exception();
    }
  };
  std::vector<std::thread> workers;
  for (std::size_t t = 1; t < threads; ++t) workers.emplace_back(run, t);
  run(0);
  for (std::thread& worker : workers) worker.join();
  for (const std::exception_ptr& failure : failures) {
    if (failure) std::rethrow_exception(failure);
  }
}

// body(i) for every i in [0, count) on all cores (as above, without state).
template <class Body>
void ParallelFor(std::size_t count, std::size_t chunk, const Body& body) {
  struct NoState {};
  ParallelForWithState<NoState>(count, chunk, 0, [&body](NoState&, std::size_t i) { body(i); });
}

}  // namespace facerig
