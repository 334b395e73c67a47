"""harmonia: mesh parameterization, texture atlases, spherical maps and editing, from numpy arrays.

The compiled library behind it computes with the interpreter lock released, on all cores, and on a
Vulkan device where one is asked for. Every call takes positions as an (n, 3) array of any float
or integer dtype and faces as an (m, 3) array of any integer dtype, in any memory order.

Quick start::

    import harmonia
    vmapping, indices, uvs = harmonia.parametrize(positions, faces)   # as xatlas.parametrize
    atlas = harmonia.atlas(positions, faces, resolution=2048)         # the whole report
    print(atlas.charts_count, atlas.coverage, atlas.l2_stretch)

Errors are the classes of :mod:`harmonia.errors`, all derived from :class:`harmonia.Error`.
"""

from . import _core
from .atlas import Atlas, Chart, atlas, parametrize, repack
from .editing import DeformationTransfer, SurfaceEditor
from .errors import (CancelledError, DeviceError, Error, FileError, FlippedTrianglesError,
                     InvalidInputError, NonManifoldError, NotADiskError, NotASphereError,
                     NotConvergedError, NumericalError, ParseError, UnsupportedError)
from .gltf import GltfDocument, atlas_gltf, read_gltf
from .mappers import DiskMapper, SphereMapper
from .maps import Cleanup, SphereMap, cleanup, cut, sphere
from .planar import compare, evaluate, unwrap
from .meshes import read_mesh, read_textured_obj, write_mesh, write_textured_obj
from .settings import blas_thread_policy, set_blas_thread_policy

#: A Vulkan device created once and shared by any number of calls and threads: pass it as
#: ``device=``. ``VulkanContext(device_name="", device_index=None, validation=False,
#: float64=False)``; ``name``, ``type`` and ``float64`` describe the device.
VulkanContext = _core.VulkanContext

__version__ = _core.__version__

__all__ = [
    "Atlas", "Chart", "atlas", "parametrize", "repack", "SphereMap", "sphere", "cut", "cleanup", "Cleanup", "SurfaceEditor", "DeformationTransfer",
    "unwrap", "evaluate", "compare", "DiskMapper", "SphereMapper",
    "read_mesh", "read_textured_obj", "write_mesh", "write_textured_obj",
    "GltfDocument", "read_gltf", "atlas_gltf",
    "VulkanContext", "set_blas_thread_policy", "blas_thread_policy",
    "Error", "InvalidInputError", "ParseError", "FileError", "NotADiskError", "NotASphereError",
    "NonManifoldError", "NotConvergedError", "NumericalError", "FlippedTrianglesError",
    "CancelledError", "UnsupportedError", "DeviceError",
]
