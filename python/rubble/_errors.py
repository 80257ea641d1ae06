"""rubble's errors as Python exceptions.

Every error of the C++ library arrives as one of these, with the attributes

- ``where``: the file and field (``scenes/a.json: bodies[3].mass``), the option
  (``World.load: iterations``) or the call (``clBuildProgram``);
- ``file`` and ``field``: ``where`` split when it names the scene that was read
  (``field`` is None for an error about the file as a whole);
- ``kind``: the library's name of the kind (``BadInput``, ``Device``, ...).
"""

from __future__ import annotations

from typing import Optional


class Error(Exception):
    """Base class of rubble's errors."""

    def __init__(self, message: str, *, where: str = "", kind: str = "Internal",
                 file: Optional[str] = None, field: Optional[str] = None) -> None:
        super().__init__(message)
        self.where = where
        self.kind = kind
        self.file = file
        self.field = field

    def __reduce__(self):
        # Keeps the attributes when the error crosses processes (a Dask worker's run).
        return (_rebuild, (type(self), str(self), self.where, self.kind, self.file, self.field))


def _rebuild(cls, message, where, kind, file, field):
    return cls(message, where=where, kind=kind, file=file, field=field)


class SceneError(Error, ValueError):
    """Bad input: a scene file or dict, a mesh, an option or an argument (the command's exit
    status 2). ``file`` and ``field`` name where it is."""


class NotSupportedError(Error, ValueError):
    """The input asks for a feature that is specified but not built (exit status 2)."""


class DeviceError(Error, RuntimeError):
    """An OpenCL call or kernel build failed, or there is no OpenCL device."""


class NumericalError(Error, ArithmeticError):
    """The simulation blew up: a state turned non-finite, the bodies' energy grew by more than
    the scene can account for, or a joint came apart (the command's exit status 3). The message
    names the body and the step; the world is then past use."""


class LimitError(Error, RuntimeError):
    """A step needed more than rubble allows it (broad-phase pairs, contact points, particle
    contacts, memory), or the particle spacing would make more particles or voxels than a world
    may have (docs/scene-format.md, "Limits"; the command's exit status 4). The message names the
    stage and the limit."""


class StepInterrupted(Error, KeyboardInterrupt):
    """A step stopped on request between two of its stages (the command's SIGINT and SIGTERM,
    exit status 130 and 143); like Ctrl-C it is a KeyboardInterrupt. The bodies are left
    part-way through the step."""


class IoError(Error, OSError):
    """A file could not be read or written."""


_CLASSES = {
    "BadInput": SceneError,
    "NotSupported": NotSupportedError,
    "Device": DeviceError,
    "Numerical": NumericalError,
    "Limit": LimitError,
    "Interrupted": StepInterrupted,
    "Io": IoError,
}


def make_error(kind: str, where: str, message: str, file: str = "") -> Error:
    """Builds the exception of a library error (called by rubble._core)."""
    cls = _CLASSES.get(kind, Error)
    text = f"{where}: {message}" if where else message
    error_file: Optional[str] = None
    field: Optional[str] = None
    if file and where == file:
        error_file = file
    elif file and where.startswith(file + ": "):
        error_file, field = file, where[len(file) + 2:]
    return cls(text, where=where, kind=kind, file=error_file, field=field)
