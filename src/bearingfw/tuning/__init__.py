"""Model tuning after the paper (section 3.3): the SDOF estimate of the stick stiffness (eq. 11),
pairing computed with measured modes (by label or MAC, where the sensors were), least-squares
calibration of any model parameter against measured frequencies, and figures of modes and MAC
tables (:mod:`bearingfw.tuning.plot`). The paper's study on its bridge is
:mod:`bearingfw.bridges.study`.

Damping from measurements (logarithmic decrements, Rayleigh coefficients) lives with the
transient analysis that uses it: :mod:`bearingfw.analysis.damping`; its two functions are
re-exported here because tuning is where measured damping enters a model.

Any structure, any parameter (:mod:`bearingfw.tuning.fit`): :func:`fit_parameters` calibrates
named parameters of a model builder (``bearingfw tune --structure SPEC --param NAME=LOW:HIGH``)
against a measured-modes file (:func:`read_measured`) or modes identified by ``bearingfw oma``
(:func:`from_identified`), pairing by MAC or label, never by index, and reports the fit, the
sensitivities ``d ln f / d ln p`` and the MAC table. The paper's K_s from identified modes
(:func:`bearingfw.bridges.study.calibrate_ks_to_identified`) is one such fit.

The measured-modes file (:mod:`bearingfw.tuning.measured`), TOML (``.toml``) or JSON, or the
output of ``bearingfw oma --json`` / ``--output`` as it is::

    source = "ambient test, 3 May"           # optional
    channels = ["G4.uz", "G12.uz", "G4.ux"]  # optional: the order of shapes given as arrays

    [[modes]]
    name = "first bending"       # optional (default: the label, else "mode <k>")
    frequency = 2.55             # Hz, required
    label = "vertical 1"         # optional: the k-th computed mode of that label
    damping = 0.021              # optional ratio, 0 <= damping < 1 (reported)
    shape = { "G4.uz" = 1.0, "G12.uz" = -0.98, "G4.ux" = 0.02 }   # optional, at "<node>.<component>"

Every mode with a shape (at the same channels): paired by MAC there. Otherwise every mode with a
label (``vertical``, ``lateral``, ``longitudinal``, ``torsional`` and k, as ``bearingfw modal``
labels the whole mode, each label once): paired by label.
"""

from bearingfw.analysis.damping import damping_ratio_from_log_decrement, rayleigh_from_ratios
from bearingfw.tuning.calibration import CalibrationReport, Variable, calibrate, evaluate
from bearingfw.tuning.fit import FitOptions, ParameterFit, channel_warnings, fit_parameters, screen_by_mac
from bearingfw.tuning.measured import (
    MeasuredModes,
    check_channels,
    from_identified,
    identified_measurements,
    measured_modes,
    read_measured,
)
from bearingfw.tuning.pairing import (
    MIN_MAC,
    PAIR_BY,
    Measurement,
    Observation,
    ObservedModes,
    Pairing,
    PairingError,
    as_measurements,
    observed_modes,
    pair_modes,
    paired_shapes,
)
from bearingfw.tuning.sdof import frequency_ratio, ks_eq11

__all__ = [
    "MIN_MAC",
    "PAIR_BY",
    "CalibrationReport",
    "FitOptions",
    "MeasuredModes",
    "Measurement",
    "Observation",
    "ObservedModes",
    "ParameterFit",
    "Pairing",
    "PairingError",
    "Variable",
    "as_measurements",
    "calibrate",
    "channel_warnings",
    "check_channels",
    "damping_ratio_from_log_decrement",
    "evaluate",
    "fit_parameters",
    "frequency_ratio",
    "from_identified",
    "identified_measurements",
    "ks_eq11",
    "measured_modes",
    "observed_modes",
    "pair_modes",
    "paired_shapes",
    "rayleigh_from_ratios",
    "read_measured",
    "screen_by_mac",
]
