"""The reusable solvers: built once, solved again after update_geometry, giving what a fresh
one-shot call gives."""

import numpy as np
import pytest

import harmonia
from conftest import corpus_path, read_obj


def bent(positions):
    """The mesh bent smoothly (a different geometry of the same connectivity)."""
    bent = positions.copy()
    size = np.ptp(positions, axis=0).max()
    bent[:, 2] += 0.1 * size * np.sin(positions[:, 0] / size * np.pi)
    return bent


def test_disk_mapper_reuses_its_analysis():
    positions, faces, _ = read_obj(corpus_path("disk", "woody.obj"))
    mapper = harmonia.DiskMapper(positions, faces)
    uv, report = mapper.solve()
    assert report["status"] == "ok"
    assert np.array_equal(uv, harmonia.unwrap(positions, faces)[0])
    # New geometry: the same map as a one-shot call on it (same pattern and ordering; the
    # factorization is made anew, so only rounding may differ: 1e-12 of the layout's size).
    other = bent(positions)
    mapper.update_geometry(other)
    uv_other, _ = mapper.solve()
    fresh, _ = harmonia.unwrap(other, faces)
    assert np.abs(uv_other - fresh).max() < 1e-12 * np.ptp(fresh, axis=0).max()
    # New boundary positions by back-substitution: the boundary vertices land exactly there.
    vertices, placed = mapper.boundary
    moved, _ = mapper.solve(placed * 0.5)
    raw, _ = harmonia.DiskMapper(other, faces).solve(placed * 0.5)
    assert np.array_equal(moved, raw)
    with pytest.raises(harmonia.InvalidInputError, match="positions has 3 rows"):
        mapper.update_geometry(positions[:3])
    with pytest.raises(harmonia.InvalidInputError, match="boundary_uv has 2 rows"):
        mapper.solve(placed[:2])


def test_sphere_mapper_reuses_its_analysis(spot):
    positions, faces = spot
    mapper = harmonia.SphereMapper(positions, faces)
    on_sphere, report = mapper.solve()
    assert np.array_equal(on_sphere, harmonia.sphere(positions, faces).positions)
    scaled = positions * 3.0 + 1.0
    mapper.update_geometry(scaled)
    again, _ = mapper.solve()
    fresh = harmonia.sphere(scaled, faces).positions
    assert np.abs(again - fresh).max() < 1e-12
