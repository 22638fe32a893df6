"""Operational modal analysis of a multichannel record: SSI-COV, stabilisation, selected modes.

:func:`identify` runs the three steps on :class:`~bearingfw.oma.io.Channels`:

1. optional band limit: with ``Criteria.fmax`` set, the channels are low-passed and resampled
   to a sampling rate of at least ``2.5 fmax`` (the band-limited resampling of
   :func:`bearingfw.motion.resample`; its FIR filter is linear-phase, so it adds no poles of its
   own). Fewer modes in the band need a lower model order, and a shorter lag in samples covers
   the slow modes: the paper analysed 0-15 Hz;
2. SSI-COV at the orders ``2 .. max_order`` (:mod:`bearingfw.oma.ssi`);
3. the stabilisation criteria and the automatic selection (:mod:`bearingfw.oma.stabilisation`),
   with the averaged spectrum of the analysed channels (:mod:`bearingfw.oma.spectrum`) for its
   peak check.

Warnings (:attr:`Identification.warnings`): candidates that fail only for appearing at too few
orders while present at every order since their first (the order is too low for them), and a
record with a single channel (its shapes are one number: MAC cannot tell modes apart).

The result keeps every pole (for the diagram), every candidate with the reasons it was rejected,
and the selected modes as
:class:`~bearingfw.oma.io.IdentifiedModes`, which :func:`~bearingfw.oma.io.write_modes` writes
for ``bearingfw tune``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import attrs
import numpy as np

from bearingfw.motion import resample
from bearingfw.oma.io import Channels, IdentifiedModes
from bearingfw.oma.spectrum import Spectrum, singular_spectrum
from bearingfw.oma.ssi import Poles, SSISettings, ssi_cov
from bearingfw.oma.stabilisation import (
    STATUS,
    Candidate,
    Criteria,
    Stability,
    accepted_modes,
    candidates,
    late_candidates,
    stability,
)
from bearingfw.parameters import ParameterError

__all__ = ["Identification", "band_limited", "identify"]

#: Resampling keeps at least this many samples per period of ``fmax`` (Nyquist at 1.25 fmax,
#: clear of the anti-alias filter's transition band).
SAMPLES_PER_PERIOD = 2.5


@attrs.frozen(eq=False)
class Identification:
    """What :func:`identify` found: the analysed channels, every pole, their stability, the candidates, the modes."""

    channels: Channels
    poles: Poles
    stability: Stability
    modes: IdentifiedModes
    settings: SSISettings
    criteria: Criteria
    decimation: int
    spectrum: Spectrum
    candidates: tuple[Candidate, ...] = ()
    warnings: tuple[str, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        """The modes file (:meth:`IdentifiedModes.to_dict`) plus the diagram's pole counts, rejections, warnings."""
        data = self.modes.to_dict()
        data["pole_counts"] = {name: int(np.sum(self.stability.status == k)) for k, name in enumerate(STATUS)}
        data["rejected"] = [c.to_dict() for c in self.candidates if not c.accepted]
        data["warnings"] = list(self.warnings)
        return data


def band_limited(channels: Channels, fmax: float) -> tuple[Channels, int]:
    """``channels`` resampled to ``q dt`` with the largest whole ``q`` keeping ``2.5 fmax`` samples per second."""
    q = int(math.floor(1.0 / (channels.dt * SAMPLES_PER_PERIOD * fmax)))
    if q < 2:
        return channels, 1
    data = np.column_stack(
        [resample(channels.data[:, j], channels.dt, q * channels.dt) for j in range(channels.n_channels)]
    )
    meta = {**channels.metadata, "resampled_from": channels.dt}
    return attrs.evolve(channels, data=data, dt=q * channels.dt, metadata=meta), q


def identify(
    channels: Channels,
    settings: SSISettings = SSISettings(),
    criteria: Criteria = Criteria(),
    references: Sequence[str] | None = None,
) -> Identification:
    """Identify the modes of ``channels`` (module docstring); ``references``: channel names (default all)."""
    if criteria.fmax is not None and criteria.fmax >= 0.5 / channels.dt:
        raise ParameterError(
            f"Criteria: fmax = {criteria.fmax:g} Hz must be below the Nyquist frequency {0.5 / channels.dt:g} Hz"
        )
    analysed, q = band_limited(channels, criteria.fmax) if criteria.fmax is not None else (channels, 1)
    index = None
    if references is not None:
        index = [analysed.names.index(n) if n in analysed.names else -1 for n in references]
        if -1 in index or not index:
            raise ParameterError(
                f"identify: references {list(references)} must be channel names among {', '.join(analysed.names)}"
            )
    poles = ssi_cov(analysed.data, analysed.dt, settings, index)
    state = stability(poles, criteria)
    spectrum = singular_spectrum(analysed.data, analysed.dt)
    found = candidates(poles, state, criteria, spectrum)
    modes = accepted_modes(poles, found)
    warnings = identification_warnings(analysed, found, poles)
    meta = {
        "source": channels.source,
        "synthetic": channels.synthetic,
        "dt": channels.dt,
        "dt_analysed": analysed.dt,
        "duration": channels.duration,
        "ssi": {
            "method": "SSI-COV",
            "max_order": settings.max_order,
            "block_rows": poles.block_rows,
            "references": list(references) if references is not None else "all",
        },
        "criteria": attrs.asdict(criteria) | {"cluster_distance": criteria.distance},
    }
    return Identification(
        analysed,
        poles,
        state,
        IdentifiedModes(channels.names, modes, meta),
        settings,
        criteria,
        q,
        spectrum,
        found,
        warnings,
    )


def identification_warnings(channels: Channels, found: tuple[Candidate, ...], poles: Poles) -> tuple[str, ...]:
    """The warnings of the module docstring."""
    out = []
    late = late_candidates(found)
    if late:
        listed = ", ".join(f"{c.frequency:.3f} Hz (from order {c.first_order})" for c in late)
        out.append(
            f"the top orders still add stable poles: {listed}, present at every order since but at too few "
            f"to count as modes; raise the order above {poles.orders[-1]} (or narrow the band with fmax)"
        )
    if channels.n_channels == 1:
        out.append("a single channel: its mode shapes are one number each, so MAC cannot pair them with a model's")
    return tuple(out)
