"""Intensity scales (data registered through the plugin hook), degrees, levels D_0..D_IV, scaling.

The default scale is the table of the design notes (upper bounds of PGA_H10, m/s^2, by t_Ha):

=============  ====  ===========  ===========  ===========  ===========
t_Ha           0     I            II           III          IV
=============  ====  ===========  ===========  ===========  ===========
<= 1.5 s       0.15  0.6          0.9          1.2          1.6
1.5 - 3 s      0.15  0.9 - 0.2 t  1.2 - 0.2 t  1.5 - 0.2 t  1.9 - 0.2 t
> 3 s          0.15  0.3          0.6          0.9          1.3
=============  ====  ===========  ===========  ===========  ===========

As data this is two breakpoints, t_Ha = 1.5 s and 3 s, with each degree's bound linear between
them and constant outside; the middle row is exactly that line (the table is continuous).
"""

from __future__ import annotations

import math
import numbers
import re
from collections.abc import Iterable, Mapping
from typing import Any

import attrs

from bearingfw.motion.errors import IntensityMismatchError, UnknownScaleError
from bearingfw.motion.metrics import has_horizontal_motion, record_pga_h10, record_t_ha
from bearingfw.motion.record import Record
from bearingfw.parameters import ParameterError
from bearingfw.plugins.contracts import IntensityScale

__all__ = [
    "DEFAULT_LEVELS",
    "DEFAULT_SCALE",
    "DEFAULT_SCALE_NAME",
    "LEVEL_NAMES",
    "IntensityLevels",
    "IntensityScale",
    "checked_level",
    "get_scale",
    "level_degree",
    "level_name",
    "record_degree",
    "scale_to_level",
    "scale_to_pga_h10",
]

DEFAULT_SCALE_NAME = "usb-pga-h10"

DEFAULT_SCALE = IntensityScale(
    name=DEFAULT_SCALE_NAME,
    degrees=("0", "I", "II", "III", "IV"),
    durations=(1.5, 3.0),
    bounds=((0.15, 0.15), (0.6, 0.3), (0.9, 0.6), (1.2, 0.9), (1.6, 1.3)),
    description=(
        "Mining-tremor intensity by PGA_H10 and t_Ha (Upper Silesian Basin; the GSI-GZW_KW-2012-A "
        "scale of the paper in kind). Boundaries from the bearingfw design notes; they reproduce the "
        "paper's classifications (0.10 m/s^2 -> 0; 0.46 m/s^2 at 3.5 s -> II). Check them against the "
        "published scale before using them for an assessment."
    ),
)

#: The paper's intensity levels, lowest first: level D_x stands for degree x of the default scale.
LEVEL_NAMES = tuple(f"D_{degree}" for degree in DEFAULT_SCALE.degrees)
_LEVEL_DEGREES = dict(zip(LEVEL_NAMES, DEFAULT_SCALE.degrees))


def _real(value: Any) -> Any:
    # Leave anything that is not a real number untouched so that the validator can name it.
    return float(value) if isinstance(value, numbers.Real) and not isinstance(value, bool) else value


def _level(index: int, default: float, doc: str):
    """The field of level ``LEVEL_NAMES[index]``: a PGA_H10 > 0 (m/s^2); errors name the level, not the field."""
    name = LEVEL_NAMES[index]

    def check(instance, attribute, value):
        if not isinstance(value, float) or not math.isfinite(value) or value <= 0:
            got = f"{type(value).__name__} {value!r}" if not isinstance(value, float) else repr(value)
            raise ParameterError(
                f"IntensityLevels: {name} = {got} is outside the allowed range {name} > 0 (PGA_H10 in m/s^2, finite)"
            )

    return attrs.field(
        default=default, converter=_real, validator=check,
        metadata={"level": name, "range": f"{name} > 0", "unit": "m/s^2", "doc": doc},
    )


@attrs.frozen
class IntensityLevels:
    """Target PGA_H10 (m/s^2) of the tremors D_0 .. D_IV (fields ``d0`` .. ``d4``).

    The defaults are the paper's D_0 = 0.10 and D_II = 0.46 m/s^2 and, for D_I, D_III and D_IV,
    values inside their degree of the default scale for every t_Ha > 3 s (degree bounds 0.15,
    0.3, 0.6, 0.9, 1.3 m/s^2 there).
    """

    d0: float = _level(0, 0.10, "D_0: degree 0 (the paper's low-energy tremor)")
    d1: float = _level(1, 0.23, "D_I: degree I")
    d2: float = _level(2, 0.46, "D_II: degree II (the paper's recorded tremor)")
    d3: float = _level(3, 0.75, "D_III: degree III")
    d4: float = _level(4, 1.10, "D_IV: degree IV")

    def __attrs_post_init__(self):
        values = attrs.astuple(self)
        if any(b <= a for a, b in zip(values, values[1:])):
            raise ParameterError(
                "IntensityLevels: the levels must increase from D_0 to D_IV, got "
                + ", ".join(f"{n} = {v:g}" for n, v in zip(LEVEL_NAMES, values))
            )

    def as_dict(self) -> dict[str, float]:
        """``{"D_0": 0.10, ..., "D_IV": 1.10}``."""
        return dict(zip(LEVEL_NAMES, attrs.astuple(self)))

    def __getitem__(self, level: str) -> float:
        return self.as_dict()[level_name(level)]

    @classmethod
    def with_overrides(cls, overrides: Mapping[Any, float] | Iterable[tuple[Any, float]] | None = None) -> IntensityLevels:
        """Defaults with some levels replaced, keyed by any spelling :func:`level_name` accepts.

        ``overrides`` is a mapping or a sequence of ``(level, value)`` pairs (as a command line
        gives them). Naming one level twice (``{"D_II": 0.5, "d2": 0.6}``) is an error, not "the
        last wins".
        """
        fields = dict(zip(LEVEL_NAMES, (f.name for f in attrs.fields(cls))))
        pairs = overrides.items() if isinstance(overrides, Mapping) else (overrides or ())
        given: dict[str, tuple[Any, float]] = {}
        for key, value in pairs:
            name = level_name(key)
            if name in given:
                raise ParameterError(
                    f"intensity level {name} is given twice (as {given[name][0]!r} = {given[name][1]!r} and "
                    f"{key!r} = {value!r}); give each level once"
                )
            given[name] = (key, value)
        return cls(**{fields[name]: value for name, (_, value) in given.items()})


DEFAULT_LEVELS = IntensityLevels()


def level_name(level: Any) -> str:
    """The canonical name ``D_0`` .. ``D_IV`` of a level given as ``D_II``, ``DII``, ``d2``, ``II`` or ``2``."""
    text = str(level).strip().upper().replace("-", "_")
    text = re.sub(r"^D_?", "", text)
    arabic = {str(i): degree for i, degree in enumerate(DEFAULT_SCALE.degrees)}
    text = arabic.get(text, text)
    name = f"D_{text}"
    if name not in _LEVEL_DEGREES:
        raise ParameterError(f"unknown intensity level {level!r}; levels: {', '.join(LEVEL_NAMES)}")
    return name


def level_degree(level: Any) -> str:
    """The degree a level stands for: ``D_II`` -> ``"II"``."""
    return _LEVEL_DEGREES[level_name(level)]


def get_scale(name: str | None = None, registry=None) -> IntensityScale:
    """The registered scale ``name`` (default: the default scale)."""
    from bearingfw.plugins import get_registry  # the registry is built on first use

    registry = registry or get_registry()
    name = name or DEFAULT_SCALE_NAME
    try:
        return registry.intensity_scales[name].value
    except KeyError:
        known = ", ".join(sorted(registry.intensity_scales)) or "none: is bearingfw installed with pip?"
        raise UnknownScaleError(f"unknown intensity scale {name!r}; known scales: {known}") from None


def record_degree(record: Record, scale: IntensityScale | None = None) -> str | None:
    """The degree of a record on ``scale`` (default :data:`DEFAULT_SCALE`) from its PGA_H10 and t_Ha;
    None (undefined) for a record with no horizontal motion, whose t_Ha is undefined."""
    if not has_horizontal_motion(record):
        return None
    scale = scale or DEFAULT_SCALE
    return scale.degree(record_pga_h10(record), record_t_ha(record))


def scale_to_pga_h10(record: Record, target: float) -> Record:
    """The record times ``target / PGA_H10(record)``: its PGA_H10 becomes ``target`` (m/s^2).

    PGA_H10 is positively homogeneous (the filter is linear, the resultant a norm), so one
    factor is exact; t_Ha and every spectral shape are unchanged.
    """
    target = float(target)
    if not math.isfinite(target) or target <= 0:
        raise ParameterError(f"target PGA_H10 must be finite and > 0 m/s^2, got {target!r}")
    current = record_pga_h10(record)
    if current <= 0:
        raise ParameterError(
            f"{record.title}: PGA_H10 is zero (no horizontal motion), it cannot be scaled to a PGA_H10; a record "
            "with no horizontal motion can only be used as recorded"
        )
    return record.scaled(target / current, target_pga_h10=target)


def scale_to_level(
    record: Record,
    level: Any,
    levels: IntensityLevels = DEFAULT_LEVELS,
    scale: IntensityScale | None = None,
) -> Record:
    """The record scaled to the PGA_H10 of intensity ``level`` (``"D_0"`` .. ``"D_IV"``).

    Raises :class:`IntensityMismatchError` if the scaled record's degree on ``scale`` is not the
    level's degree (t_Ha, which scaling does not change, can move a degree's boundaries).
    """
    name = level_name(level)
    return checked_level(record, scale_to_pga_h10(record, levels[name]), name, levels[name], scale)


def checked_level(record: Record, scaled: Record, level: Any, target: float, scale: IntensityScale | None = None) -> Record:
    """``scaled`` (``record`` scaled to PGA_H10 = ``target``, the value of ``level``) with ``level``,
    ``degree`` and ``scale`` in its metadata, if its degree on ``scale`` is the level's degree;
    else :class:`IntensityMismatchError` naming the degree's bounds at the record's t_Ha. The
    degree is judged at ``target`` itself, not at the scaled record's PGA_H10 (equal up to
    rounding), so that a level on a degree's bound stays in that degree."""
    scale = scale or DEFAULT_SCALE
    name = level_name(level)
    duration = record_t_ha(scaled)
    degree = scale.degree(target, duration)
    wanted = level_degree(name)
    if degree != wanted:
        bounds = scale.upper_bounds(duration)
        index = scale.degrees.index(wanted)
        low = bounds[index - 1] if index else 0.0
        raise IntensityMismatchError(
            f"{record.title} scaled to {name} (PGA_H10 = {target:g} m/s^2) has t_Ha = {duration:.2f} s and is "
            f"degree {degree}, not {wanted}, on scale {scale.name!r}: degree {wanted} needs "
            f"{low:.3g} < PGA_H10 <= {bounds[index]:.3g} m/s^2 at that t_Ha; choose another level value"
        )
    return attrs.evolve(scaled, metadata={**scaled.metadata, "level": name, "degree": degree, "scale": scale.name})
