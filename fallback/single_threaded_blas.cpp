#include "fallback/single_threaded_blas.h"

#include <dlfcn.h>

#include <atomic>
#include <mutex>

#include "harmonia/blas_threads.h"

namespace harmonia {
namespace {

std::atomic<BlasThreadPolicy>& policy_now() {
  static std::atomic<BlasThreadPolicy> policy{BlasThreadPolicy::leave_alone};
  return policy;
}

}  // namespace

BlasThreadPolicy set_blas_thread_policy(BlasThreadPolicy policy) {
  return policy_now().exchange(policy);
}

BlasThreadPolicy blas_thread_policy() { return policy_now().load(); }

}  // namespace harmonia

namespace harmonia::detail {
namespace {

using SetThreads = void (*)(int);
using GetThreads = int (*)();

// OpenBLAS's thread-count functions, looked up among the libraries the process has loaded
// (CHOLMOD's BLAS): in the global scope, else in the BLAS library itself when harmonia was loaded
// with local symbols. Null with another BLAS.
struct OpenBlasThreads {
  SetThreads set = nullptr;
  GetThreads get = nullptr;

  OpenBlasThreads() {
    if (look_up(RTLD_DEFAULT)) return;
    for (const char* library : {"libblas.so.3", "libopenblas.so.0"}) {
      // RTLD_NOLOAD: only a library that is loaded already; the reference is dropped at once
      // (the library stays, CHOLMOD holds it).
      void* handle = dlopen(library, RTLD_NOW | RTLD_NOLOAD);
      if (handle == nullptr) continue;
      const bool found = look_up(handle);
      dlclose(handle);
      if (found) return;
    }
  }

  bool look_up(void* scope) {
    set = reinterpret_cast<SetThreads>(dlsym(scope, "openblas_set_num_threads"));
    get = reinterpret_cast<GetThreads>(dlsym(scope, "openblas_get_num_threads"));
    if (set != nullptr && get != nullptr) return true;
    set = nullptr;
    get = nullptr;
    return false;
  }
};

const OpenBlasThreads& openblas_threads() {
  static const OpenBlasThreads functions;
  return functions;
}

// The guards alive in the process and the count the first one found.
struct GuardCount {
  std::mutex mutex;
  int guards = 0;
  int saved_threads = 0;
};

GuardCount& guard_count() {
  static GuardCount count;
  return count;
}

}  // namespace

SingleThreadedBlas::SingleThreadedBlas() {
  const OpenBlasThreads& functions = openblas_threads();
  if (functions.set == nullptr) return;
  GuardCount& count = guard_count();
  const std::lock_guard<std::mutex> lock(count.mutex);
  if (count.guards++ == 0) {
    count.saved_threads = functions.get();
    functions.set(1);
  }
  held_ = true;
}

SingleThreadedBlas::~SingleThreadedBlas() { release(); }

void SingleThreadedBlas::release() {
  if (!held_) return;
  held_ = false;
  const OpenBlasThreads& functions = openblas_threads();
  GuardCount& count = guard_count();
  const std::lock_guard<std::mutex> lock(count.mutex);
  if (--count.guards == 0) functions.set(count.saved_threads);
}

bool SingleThreadedBlas::available() { return openblas_threads().set != nullptr; }

bool SingleThreadedBlas::allowed() {
  return available() &&
         blas_thread_policy() == BlasThreadPolicy::hold_during_split_factorizations;
}

int SingleThreadedBlas::threads_now() {
  const OpenBlasThreads& functions = openblas_threads();
  return functions.get != nullptr ? functions.get() : 0;
}

}  // namespace harmonia::detail
