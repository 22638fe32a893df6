"""Errors of the motion layer; each names what the user must look at."""

from __future__ import annotations

from pathlib import Path

__all__ = [
    "IntensityMismatchError",
    "RecordFormatError",
    "UnknownReaderError",
    "UnknownScaleError",
    "VerticalComponentError",
]


class RecordFormatError(ValueError):
    """A record file is malformed. The message reads ``FILE, line N: what is wrong``.

    ``line`` is 1-based; it is ``None`` when the problem is not on one line (for ``.npz`` files
    the location names the array and the index instead).
    """

    def __init__(self, path: str | Path, line: int | None, message: str, location: str | None = None):
        self.path = str(path)
        self.line = line
        self.location = location
        where = self.path
        if line is not None:
            where += f", line {line}"
        if location:
            where += f", {location}"
        super().__init__(f"{where}: {message}")


class _NameError(KeyError):
    def __str__(self) -> str:  # KeyError would show the message in quotes
        return str(self.args[0])


class UnknownReaderError(_NameError):
    """No record reader of that name is registered, or none can read a file."""


class UnknownScaleError(_NameError):
    """No intensity scale of that name is registered."""


class IntensityMismatchError(ValueError):
    """A record scaled to an intensity level falls outside that level's degree."""


class VerticalComponentError(RecordFormatError):
    """A component that looks vertical is mapped to a horizontal axis (x or y) without
    ``vertical_as_horizontal``. ``axis`` is the axis, ``evidence`` the reasons
    (:class:`bearingfw.motion.vertical.Evidence`)."""

    def __init__(self, path: str | Path, axis: str, evidence, message: str):
        self.axis = axis
        self.evidence = tuple(evidence)
        super().__init__(path, None, message)
