// OpenBLAS's thread count, set for a scope. Two builds at once (lid_choice.h)
// each calling a multi-threaded OpenBLAS made the registrations 4x slower
// (their spinning BLAS threads fight for the cores); with one BLAS thread
// each they share the cores well. Found at run time: other BLAS libraries
// (Debian's reference BLAS) have no threads and no such call.
#pragma once

namespace facerig {

class ScopedBlasThreads {
 public:
  explicit ScopedBlasThreads(int threads);
  ~ScopedBlasThreads();
  ScopedBlasThreads(const ScopedBlasThreads&) = delete;
  ScopedBlasThreads& operator=(const ScopedBlasThreads&) = delete;

 private:
  int previous_ = 0;  // 0: not OpenBLAS, nothing set
};

}  // namespace facerig
