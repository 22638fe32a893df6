"""Model tuning after the paper (section 3.3): the SDOF estimate of the stick stiffness (eq. 11),
pairing computed with measured modes (by label or MAC, where the sensors were), least-squares
calibration of any model parameter against measured frequencies, and figures of modes and MAC
tables (:mod:`bearingfw.tuning.plot`). The paper's study on its bridge is
:mod:`bearingfw.bridges.study`.

Damping from measurements (logarithmic decrements, Rayleigh coefficients) lives with the
transient analysis that uses it: :mod:`bearingfw.analysis.damping`; its two functions are
re-exported here because tuning is where measured damping enters a model.
"""

from bearingfw.analysis.damping import damping_ratio_from_log_decrement, rayleigh_from_ratios
from bearingfw.tuning.calibration import CalibrationReport, Variable, calibrate, evaluate
from bearingfw.tuning.pairing import (
    MIN_MAC,
    PAIR_BY,
    Measurement,
    Observation,
    ObservedModes,
    Pairing,
    PairingError,
    as_measurements,
    identified_measurements,
    observed_modes,
    pair_modes,
    paired_shapes,
)
from bearingfw.tuning.sdof import frequency_ratio, ks_eq11

__all__ = [
    "MIN_MAC",
    "PAIR_BY",
    "CalibrationReport",
    "Measurement",
    "Observation",
    "ObservedModes",
    "Pairing",
    "PairingError",
    "Variable",
    "as_measurements",
    "calibrate",
    "damping_ratio_from_log_decrement",
    "evaluate",
    "frequency_ratio",
    "identified_measurements",
    "ks_eq11",
    "observed_modes",
    "pair_modes",
    "paired_shapes",
    "rayleigh_from_ratios",
]
