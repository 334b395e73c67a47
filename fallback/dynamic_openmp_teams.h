#pragma once
// Internal: OpenMP teams sized to the free cores while CHOLMOD factorizes.
//
// CHOLMOD's supernodal factorization opens OpenMP parallel regions whose team size was fixed when
// it was built (CHOLMOD_OMP_NUM_THREADS, 4 in Debian's SuiteSparse 5), beside OpenBLAS's own
// threads. On a machine with fewer cores the teams oversubscribe it, and threads spinning between
// regions take turns with the ones doing the work: on 2 cores every factorization took 35-40 %
// longer than with dynamic team sizes (OMP_DYNAMIC=true), which let the runtime shrink a team to
// the cores that are free. This guard asks for dynamic teams for its lifetime and then restores
// the caller's setting. The setting (OpenMP's dyn-var) belongs to the calling thread, so neither
// the application's other threads nor its own later regions see a change. The regions only
// scatter updates into disjoint entries of the factor, so the team size does not change a bit of
// the result (tests/test_orderings.cpp checks it).

namespace harmonia::detail {

class DynamicOpenMpTeams {
 public:
  DynamicOpenMpTeams();
  ~DynamicOpenMpTeams();
  DynamicOpenMpTeams(const DynamicOpenMpTeams&) = delete;
  DynamicOpenMpTeams& operator=(const DynamicOpenMpTeams&) = delete;

  //! Whether the calling thread's OpenMP teams are dynamic now (false without OpenMP).
  [[nodiscard]] static bool dynamic_now();

 private:
  int previous_ = 0;
};

}  // namespace harmonia::detail
