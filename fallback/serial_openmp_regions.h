#pragma once
// Internal: the calling thread's OpenMP regions run on that thread alone while CHOLMOD factorizes.
//
// CHOLMOD's supernodal factorization opens OpenMP parallel regions whose team size was fixed when
// it was built (CHOLMOD_OMP_NUM_THREADS, 4 in Debian's SuiteSparse 5). They only clear and
// scatter a supernode's entries between BLAS calls, and OpenBLAS already runs those calls on
// every core: the team's workers spin between regions and take turns with OpenBLAS's threads.
// On 2 cores one factorization of the 827K-face mesh's cotangent Laplacian took 1.6-2.9 s with
// CHOLMOD's teams (dynamic team sizes, which libgomp takes from the 15-minute load average,
// changed little) against a steady 1.1 s with serial regions, and the two threads of a split
// factorization (subtree_parallel_cholesky.h) each brought two more spinning workers.
//
// The guard sets the calling thread's max-active-levels to 0, so that its regions get a team of
// one, and restores the value at the end. The setting (an OpenMP ICV) belongs to the calling
// thread: the application's other threads and its own later regions see no change. The regions
// scatter into disjoint entries, so the team size does not change a bit of the result.

namespace harmonia::detail {

class SerialOpenMpRegions {
 public:
  SerialOpenMpRegions();
  ~SerialOpenMpRegions();
  SerialOpenMpRegions(const SerialOpenMpRegions&) = delete;
  SerialOpenMpRegions& operator=(const SerialOpenMpRegions&) = delete;

  //! Whether the calling thread's regions run on it alone now (true without OpenMP).
  [[nodiscard]] static bool serial_now();

 private:
  int previous_ = 0;
};

}  // namespace harmonia::detail
