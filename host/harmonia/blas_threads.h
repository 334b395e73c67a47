#pragma once
//! \file blas_threads.h
//! \brief Whether harmonia may change OpenBLAS's thread count, which is one setting for the whole
//! process.
//!
//! The CPU backend factorizes a large system (linear ABF's reduced angle system, the UV systems of
//! LSCM and of the reconstruction from angles) fastest as two halves on two threads side by side.
//! Each half's BLAS calls must then run on one thread: OpenBLAS's thread pool serves one caller at
//! a time, and two callers queue for it and spin. OpenBLAS offers no per-thread setting, only a
//! process-wide count, so holding it to one also makes the BLAS calls that the application runs
//! on its own threads meanwhile single-threaded (their results do not change, only their speed).
//! A library embedded in an application does not do that unless the application says so.
//!
//! With another BLAS than OpenBLAS there is no count to hold: the policy changes nothing and the
//! systems are factorized whole.

namespace harmonia {

enum class BlasThreadPolicy {
  //! harmonia never changes OpenBLAS's thread count (the library's default). A large system is
  //! factorized whole on the calling thread, its BLAS calls on OpenBLAS's threads: slower on large
  //! meshes (docs/cpp-api.md, "Process-wide settings", has the figures).
  leave_alone,
  //! While two halves of a system are factorized side by side, OpenBLAS's count is held to one
  //! thread and then restored to the value found (also when the call throws or is cancelled).
  //! The harmonia program's choice: it owns its process.
  hold_during_split_factorizations,
};

//! Sets the policy for the factorizations analyzed from now on, in every thread; returns the
//! previous policy. A factorization keeps the choice made when it was analyzed (a mapper object
//! that refactorizes after update_geometry keeps splitting, or not).
BlasThreadPolicy set_blas_thread_policy(BlasThreadPolicy policy);

//! The policy now.
[[nodiscard]] BlasThreadPolicy blas_thread_policy();

}  // namespace harmonia
