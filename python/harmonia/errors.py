"""The exceptions harmonia raises: one class per status of the C++ library (harmonia/types.h).

Every one derives from :class:`Error`, carries the library's status name in ``status`` and the
same one-line message the ``harmonia`` program prints. Where a Python exception means the same
thing, the class derives from it too, so that code catching ``ValueError`` or ``OSError`` keeps
working: bad arguments are :class:`InvalidInputError`, a ``ValueError``; files that cannot be
read or written are :class:`FileError`, an ``OSError``.
"""


class Error(Exception):
    """Anything harmonia refuses or fails at. ``status`` names the library's status."""

    status = "error"

    def __init__(self, message):
        super().__init__(message)
        self.message = message


class InvalidInputError(Error, ValueError):
    """Bad numbers, shapes or indices in the input (the message names the argument, vertex or face)."""

    status = "invalid_input"


class ParseError(Error, ValueError):
    """A mesh file could not be parsed (the message names the file and line or byte)."""

    status = "parse_error"


class FileError(Error, OSError):
    """A file could not be opened, read or written (the message names it)."""

    status = "io_error"


class NotADiskError(Error):
    """The method needs a disk (one boundary loop, genus 0); ``cut`` makes one."""

    status = "not_a_disk"


class NotASphereError(Error):
    """The method needs a closed genus-0 surface (spherical maps)."""

    status = "not_a_sphere"


class NonManifoldError(Error):
    """A non-manifold edge or vertex, or inconsistent orientation."""

    status = "non_manifold"


class NotConvergedError(Error):
    """An iterative solver stopped at its iteration cap above its tolerance."""

    status = "not_converged"


class NumericalError(Error, ArithmeticError):
    """A factorization failed, or a result was not finite."""

    status = "numerical_failure"


class FlippedTrianglesError(Error):
    """The map was computed but has flipped or zero-area triangles."""

    status = "flipped_triangles"


class CancelledError(Error):
    """The call was cancelled (``progress`` returned False, ``cancel`` was set, or Ctrl+C)."""

    status = "cancelled"


class UnsupportedError(Error):
    """An option or feature this build or backend lacks."""

    status = "unsupported"


class DeviceError(Error):
    """The compute device is missing or failed (``backend="vulkan"`` without one, device lost, ...)."""

    status = "device_failure"


#: The class of each status name of the library (the compiled core raises through this table).
ERROR_OF_STATUS = {
    cls.status: cls
    for cls in (InvalidInputError, ParseError, FileError, NotADiskError, NotASphereError,
                NonManifoldError, NotConvergedError, NumericalError, FlippedTrianglesError,
                CancelledError, UnsupportedError, DeviceError)
}


def error_for(status, message):
    """The exception for a status name and its message (Error for a name not in the table)."""
    return ERROR_OF_STATUS.get(status, Error)(message)
