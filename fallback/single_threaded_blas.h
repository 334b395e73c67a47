#pragma once
// Internal: OpenBLAS held to one thread per call while several of harmonia's threads factorize at
// once (subtree_parallel_cholesky.h).
//
// CHOLMOD's supernodal factorization spends its time in BLAS. OpenBLAS (Debian's default BLAS)
// runs a large call on its own pool of threads, and that pool serves one caller at a time: two
// threads factorizing side by side then queue for it and spin while they wait. On 2 cores two
// halves of a 2x2-block system took 3-5 s side by side with the pool against 1.0-1.1 s with
// single-threaded calls (one factorization of the whole: 1.7 s). This guard sets OpenBLAS's
// thread count to one while at least one guard lives and restores the count found by the first
// one when the last ends, so that concurrent maps in one application nest correctly.
//
// The count is OpenBLAS's process-wide setting: BLAS calls that the application makes on other
// threads meanwhile run single-threaded too (their results do not change, only their speed).
// So a guard is made only where the caller allowed it (allowed(): the policy of
// harmonia/blas_threads.h is hold_during_split_factorizations); the guard itself does not ask.
// OpenBLAS is found at run time (its `openblas_set_num_threads`); with another BLAS the guard
// does nothing and available() is false.

namespace harmonia::detail {

class SingleThreadedBlas {
 public:
  SingleThreadedBlas();
  ~SingleThreadedBlas();
  SingleThreadedBlas(const SingleThreadedBlas&) = delete;
  SingleThreadedBlas& operator=(const SingleThreadedBlas&) = delete;

  //! Ends this guard before its destruction (once; the destructor then does nothing): a thread
  //! with nothing left to do hands its core back to the BLAS calls still running elsewhere.
  void release();

  //! Whether the process's BLAS is OpenBLAS, whose thread count the guard can set.
  [[nodiscard]] static bool available();
  //! Whether a guard may be made: available() and the caller's policy lets harmonia hold the
  //! count (set_blas_thread_policy).
  [[nodiscard]] static bool allowed();
  //! OpenBLAS's thread count now (0 where unavailable).
  [[nodiscard]] static int threads_now();

 private:
  bool held_ = false;
};

}  // namespace harmonia::detail
