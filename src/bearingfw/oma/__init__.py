"""Operational modal analysis: measured ambient accelerations -> identified modes -> calibration.

The paper's step 1 starts from modes identified on the bridge (section 2.3, 3.1-3.2): stochastic
subspace identification of ambient vibration, a stabilisation diagram, and damping from the free
decay of a jumping test. This package does the same on any multichannel record:

- :mod:`~bearingfw.oma.io`: channel files (CSV, NPZ) whose names map to model DOFs
  (``"GA32.uz"``), and the identified-modes JSON that ``bearingfw tune --measured`` reads;
- :mod:`~bearingfw.oma.ssi`: covariance-driven SSI (correlations, block Toeplitz, SVD, poles of
  every model order);
- :mod:`~bearingfw.oma.stabilisation`: the stability criteria between orders (frequency, damping,
  MAC; the paper's 2 %, 2 %, 90 %) and the automatic selection of modes by clustering, with
  checks that keep noise out (presence from order to order, real shapes, a spectral peak);
- :mod:`~bearingfw.oma.identify`: the three steps on a record, with an optional band limit;
- :mod:`~bearingfw.oma.decay`: logarithmic decrement of a band-passed free decay;
- :mod:`~bearingfw.oma.simulate`: simulated ambient tests of a linear model (exact modal
  superposition), to plan sensors and to check the method;
- :mod:`~bearingfw.oma.spectrum`: the averaged spectrum (CMIF) and the peak check of the selection;
- :mod:`~bearingfw.oma.plot`: the figures (imported on demand: it loads matplotlib).

Layer: between motion and tuning. It may import the model, analysis and motion layers and
:mod:`bearingfw.plotting`; tuning and the CLI import it; it never imports bridges, tuning,
experiment or cli.
"""

from __future__ import annotations

import importlib

#: Each public name and the module that defines it. They load on first use (PEP 562), so that a
#: layer that needs only the modes file (tuning imports :mod:`bearingfw.oma.io`) does not load
#: the identification (scipy's clustering, signal processing).
_EXPORTS = {
    "Decay": "decay",
    "DecayFilter": "decay",
    "log_decrement": "decay",
    "Identification": "identify",
    "identify": "identify",
    "Channels": "io",
    "IdentifiedMode": "io",
    "IdentifiedModes": "io",
    "channel_dofs": "io",
    "parse_channel": "io",
    "read_channels": "io",
    "read_modes": "io",
    "write_modes": "io",
    "modal_damping": "simulate",
    "simulate_ambient": "simulate",
    "Spectrum": "spectrum",
    "singular_spectrum": "spectrum",
    "Poles": "ssi",
    "SSISettings": "ssi",
    "ssi_cov": "ssi",
    "STATUS": "stabilisation",
    "Candidate": "stabilisation",
    "Criteria": "stabilisation",
    "Stability": "stabilisation",
    "select_modes": "stabilisation",
    "stability": "stabilisation",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name not in _EXPORTS:
        raise AttributeError(f"module 'bearingfw.oma' has no attribute {name!r}")
    value = getattr(importlib.import_module(f"bearingfw.oma.{_EXPORTS[name]}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_EXPORTS))
