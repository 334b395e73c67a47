"""The package on a Vulkan device: lavapipe with the validation layer on, cross-checked against
the CPU; one context shared by threads; and the device error where there is no device."""

import os
import subprocess
import sys
import textwrap
import threading

import numpy as np
import pytest

import harmonia
from conftest import corpus_path


def run_python(code, **environment):
    """Runs `code` in a fresh interpreter (a Vulkan loader reads its environment once)."""
    env = dict(os.environ, **environment)
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, env=env)


def test_atlas_on_lavapipe_matches_the_cpu_with_validation_on():
    spot = corpus_path("closed", "spot.obj")
    run = run_python(f"""
        import numpy as np, harmonia
        V, F = harmonia.read_mesh({str(spot)!r})
        device = harmonia.VulkanContext(device_name="llvmpipe", validation=True)
        on_device = harmonia.atlas(V, F, backend="vulkan", device=device)
        on_cpu = harmonia.atlas(V, F, backend="cpu")
        assert on_device.report["backend"] == "vulkan", on_device.report
        assert (on_device.chart_of_face == on_cpu.chart_of_face).all()
        # The device solves the charts' linear ABF systems to a relative residual of 1e-10 (in
        # float, refined in double); with the systems' conditioning (below 1e2 for these charts)
        # the layouts agree to 1e-8 of a chart's size. Compared: every face's edge lengths in
        # the chart's own units (texels over the texel density), which the packing's turn and
        # shift leave alone. Where the charts land is not compared: the density search ends at a
        # packing with no row to spare, which layouts 1e-10 apart can fit or miss by one texel.
        def lengths(atlas):
            texels = atlas.corner_uv * np.array([atlas.resolution, atlas.height])
            edges = texels - np.roll(texels, 1, axis=1)
            return np.linalg.norm(edges, axis=2) / atlas.texels_per_unit
        difference = np.abs(lengths(on_device) - lengths(on_cpu)).max()
        assert difference < 1e-8, difference
        metrics = on_device.metrics
        assert metrics["flipped_triangles"] == 0 and metrics["overlapping_texels"] == 0
        print("ok", difference)
    """)
    assert run.returncode == 0, run.stderr
    assert run.stdout.startswith("ok")
    # The validation layer writes every warning and error to stderr: it must have said nothing.
    assert "Validation" not in run.stderr and "VUID" not in run.stderr, run.stderr


def test_without_a_device_vulkan_raises_and_auto_falls_back():
    spot = corpus_path("closed", "spot.obj")
    run = run_python(f"""
        import harmonia
        V, F = harmonia.read_mesh({str(spot)!r})
        try:
            harmonia.atlas(V, F, backend="vulkan")
            print("no error")
        except harmonia.DeviceError as error:
            print("DeviceError:", error)
        print("auto:", harmonia.atlas(V, F).report["backend"])
    """, VK_ICD_FILENAMES="/nonexistent/icd.json", VK_DRIVER_FILES="/nonexistent/icd.json")
    assert run.returncode == 0, run.stderr
    assert "DeviceError: texture atlas: the Vulkan backend is unavailable" in run.stdout
    assert "auto: cpu" in run.stdout


def test_one_context_shared_by_two_threads(spot):
    positions, faces = spot
    device = harmonia.VulkanContext(device_name="llvmpipe")
    serial = harmonia.atlas(positions, faces, backend="vulkan", device=device).corner_uv
    results = [None, None]

    def run(slot):
        results[slot] = harmonia.atlas(positions, faces, backend="vulkan", device=device).corner_uv

    threads = [threading.Thread(target=run, args=(slot,)) for slot in (0, 1)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert np.array_equal(results[0], serial) and np.array_equal(results[1], serial)
