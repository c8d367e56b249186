// Runs independent iterations of a loop on all cores.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace facerig {

// Calls body(i) for every i in [0, count), chunks of `chunk` indices handed to
// the next free thread (the calling thread is one of them). Each iteration
// must write only its own outputs, so the result does not depend on the
// split. The first exception (in thread order) is rethrown on the caller.
template <class Body>
void ParallelFor(std::size_t count, std::size_t chunk, const Body& body) {
  chunk = std::max<std::size_t>(chunk, 1);
  const std::size_t chunks = (count + chunk - 1) / chunk;
  const std::size_t threads =
      std::min<std::size_t>(std::max(1u, std::thread::hardware_concurrency()), std::max<std::size_t>(chunks, 1));
  std::vector<std::exception_ptr> failures(threads);
  std::atomic<std::size_t> next{0};
  auto run = [&](std::size_t t) {
    try {
      for (std::size_t c = next++; c < chunks; c = next++) {
        const std::size_t end = std::min(count, (c + 1) * chunk);
        for (std::size_t i = c * chunk; i < end; ++i) body(i);
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

}  // namespace facerig
