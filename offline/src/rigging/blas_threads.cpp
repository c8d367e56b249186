#include "rigging/blas_threads.h"

#include <dlfcn.h>

namespace facerig {
namespace {

using GetThreads = int (*)();
using SetThreads = void (*)(int);

GetThreads OpenBlasGet() { return reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads")); }
SetThreads OpenBlasSet() { return reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads")); }

}  // namespace

ScopedBlasThreads::ScopedBlasThreads(int threads) {
  const GetThreads get = OpenBlasGet();
  const SetThreads set = OpenBlasSet();
  if (get == nullptr || set == nullptr) return;
  previous_ = get();
  set(threads);
}

ScopedBlasThreads::~ScopedBlasThreads() {
  if (previous_ > 0) OpenBlasSet()(previous_);
}

}  // namespace facerig
