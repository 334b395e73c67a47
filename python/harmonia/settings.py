"""Process-wide settings. harmonia changes none of them by itself; an application that owns its
process (a batch script, a worker) may choose them."""

from . import _core


def set_blas_thread_policy(policy):
    """Whether harmonia may hold OpenBLAS's process-wide thread count to one while it factorizes
    two halves of a large system side by side -> the previous policy.

    ``"leave_alone"`` (the default): harmonia never changes it; a large system is factorized
    whole. ``"hold_during_split_factorizations"``: faster on large meshes, and what the
    ``harmonia`` program chooses; the two factorizations round differently, so the program's
    results are reproduced bit for bit under this policy. It affects BLAS calls the application
    makes on other threads meanwhile (their speed, not their results).
    """
    return _core.set_blas_thread_policy(policy)


def blas_thread_policy():
    """The policy now: ``"leave_alone"`` or ``"hold_during_split_factorizations"``."""
    return _core.blas_thread_policy()
