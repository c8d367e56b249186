// Counts global operator new calls made by the current thread, to prove that
// per-frame code does not allocate. The test binaries replace operator new.
#pragma once

#include <cstddef>

namespace facerig::test {

// Allocations made by this thread while the guard lived.
class AllocationCounter {
 public:
  AllocationCounter();
  ~AllocationCounter();
  AllocationCounter(const AllocationCounter&) = delete;
  AllocationCounter& operator=(const AllocationCounter&) = delete;
  std::size_t count() const;

 private:
  std::size_t start_;
};

}  // namespace facerig::test
