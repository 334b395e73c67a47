#pragma once
// Internal: the first round of linear ABF (abf/linear_abf.cpp) of many disk meshes at once, their
// angle systems solved together on one backend: many small systems (a texture atlas' charts) in
// one device submission instead of one PCG per mesh.
//
// Per mesh, on the host and exactly as linear_abf() does it: the mesh scaled to unit size,
// validated, its estimate (3.2.2), the constraints linearized there and the reduced SPD system of
// ReducedAngleSystem (the triangle rows eliminated; abf/linear_abf_round.h,
// reduced_angle_system.h). The reduced systems become the diagonal blocks of one matrix, uploaded
// once and solved by one Backend::block_pcg (Jacobi-PCG, every block its own system with its own
// stopping test, from a zero start like linear_abf's first round on a device). Per mesh again: the
// errors e, the angles alpha + e and, where they lie in (0, pi), the least-squares reconstruction
// on the CPU (angles_to_uv_validated; small systems, factorized directly).
//
// A mesh's batched round is final where linear_abf() would stop after its first round too: the
// block converged (or stalled within kLinearAbfAcceptedSolveResidual), the angles are valid, the
// layout has no flipped or zero-area triangle and (with avoid_boundary_crossings) no boundary
// crossing. Its result is then linear_abf()'s one-round result up to the solve's tolerance
// (report.rounds = 1, report.solver "block-pcg-jacobi (reduced, N meshes in one solve)", the
// device's backend, precision and iterations). With LinearAbfOptions::rounds > 1, which asks for
// more rounds than one, no round is batched.

#include <optional>
#include <vector>

#include "backend/backend.h"
#include "harmonia/abf.h"
#include "harmonia/linear_abf.h"
#include "harmonia/mesh.h"

namespace harmonia::detail {

//! The batched first rounds: per mesh (in order) its final result, an error result for a mesh or
//! options that linear_abf() refuses (the same status and message), or nothing where the round is
//! not final (linear_abf() would go on; so does the caller). options.solver_options gives the
//! block PCG's tolerance and iteration cap and its progress callback (stage "block_pcg"; a
//! cancellation cancels every mesh of the batch); `backend` solves the blocks (any backend; the
//! CPU's solves them one by one). The per-mesh host work runs on `threads` threads (0: one per
//! core). Meshes must outlive the call.
[[nodiscard]] std::vector<std::optional<AngleMapResult>> linear_abf_first_rounds(
    const std::vector<const Mesh*>& meshes, const LinearAbfOptions& options, Backend& backend,
    int threads = 1);

//! linear_abf() of every mesh: the batched first rounds, and linear_abf(mesh, options) for each
//! mesh whose batched round is not final, so that no result is worse than linear_abf()'s.
[[nodiscard]] std::vector<AngleMapResult> linear_abf_batch(const std::vector<const Mesh*>& meshes,
                                                           const LinearAbfOptions& options,
                                                           Backend& backend, int threads = 1);

}  // namespace harmonia::detail
