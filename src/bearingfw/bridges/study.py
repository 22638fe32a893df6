"""The paper's tuning study on the reference bridge: observation, step 1, step 2, damping.

This module joins :mod:`bearingfw.bridges` (the model) and :mod:`bearingfw.tuning` (the
method); it and the defaults script :mod:`bearingfw.bridges.calibrate_defaults` are the only
bridge modules that import tuning, and nothing in tuning imports bridges.

- :func:`deck_observation`: the paper's sensors saw the deck's vertical and transverse motion,
  so its modes are the deck's (``DECK_COMPONENTS``, ``DECK_SHARE``); :func:`modes` pairs a
  model's modes with Table 2's that way.
- :func:`ks_estimate`: eq. (11) with the pillars' K_c, the untuned model's lateral frequency
  f_a and the measured one f_b.
- :func:`calibrate_ks` (step 1): least squares on K_s of the M1 model (linear springs on the
  sliding directions) against the measured frequencies of Table 2.
- :func:`tuned_bridge` (step 2): the M2 model, regularized Coulomb with the stick stiffness
  K_s and ``mu = 0.04``, for time histories.
- :func:`measured_damping`: the measured decrements as damping ratios and Rayleigh coefficients.
"""

from __future__ import annotations

from collections.abc import Mapping

from bearingfw.analysis import ModalResult
from bearingfw.analysis.damping import damping_ratio_from_log_decrement, rayleigh_from_ratios
from bearingfw.bridges.paper import DAMPING_RATIOS, FRICTION, LOG_DECREMENTS, MODES, TABLE2_OMA
from bearingfw.bridges.parameters import BridgeParameters
from bearingfw.bridges.presets import DEFAULT_KS, reference_bridge
from bearingfw.bridges.reference import DECK_COMPONENTS, DECK_SHARE, deck_nodes
from bearingfw.model import Model
from bearingfw.tuning import CalibrationReport, Observation, Pairing, calibrate, evaluate, ks_eq11

__all__ = [
    "KS_BOUNDS",
    "N_MODES",
    "calibrate_ks",
    "deck_observation",
    "ks_estimate",
    "measured_damping",
    "modes",
    "paper_measurements",
    "tuned_bridge",
]

#: Search range of K_s in step 1 (N/m): from nearly free to nearly rigid sliding bearings.
KS_BOUNDS = (1e7, 1e11)
#: Modes computed per trial: enough to reach the torsional mode near 14 Hz.
N_MODES = 40


def deck_observation(params: BridgeParameters = BridgeParameters()) -> Observation:
    """The paper's sensors: the deck's vertical and transverse motion (``DECK_COMPONENTS``, ``DECK_SHARE``)."""
    return Observation(deck_nodes(params), components=DECK_COMPONENTS, min_share=DECK_SHARE)


def paper_measurements(column: Mapping[str, float] = TABLE2_OMA) -> list[tuple[str, float]]:
    """Table 2's modes in the paper's order as ``(label, frequency)`` (default: the measured column)."""
    return [(mode, column[mode]) for mode in MODES]


def modes(
    preset: str = "M0", params: BridgeParameters = BridgeParameters(), measured=None, ks: float = DEFAULT_KS
) -> tuple[ModalResult, Pairing]:
    """The modal analysis of the bridge with ``preset`` and its pairing with ``measured`` (default: Table 2 OMA)."""
    measured = paper_measurements() if measured is None else measured
    model = reference_bridge(preset, ks=ks, params=params)
    return evaluate(model, measured, observation=deck_observation(params), n_modes=N_MODES)


def ks_estimate(
    params: BridgeParameters = BridgeParameters(), f_b: float = TABLE2_OMA["lateral 1"]
) -> tuple[float, float]:
    """Eq. (11) for this model: ``(K_s, f_a)`` with f_a the untuned model's first lateral frequency."""
    f_a = float(modes("M0", params, [("lateral 1", f_b)])[1].frequencies[0])
    return ks_eq11(params.pillar_stiffness, f_a, f_b), f_a


def calibrate_ks(
    params: BridgeParameters = BridgeParameters(),
    measured=None,
    initial: float | None = None,
    by: str = "label",
    n_modes: int = N_MODES,
) -> CalibrationReport:
    """Step 1: fit K_s of the M1 model to ``measured`` (default: Table 2's OMA column).

    Starts from ``initial`` (default: the eq. 11 estimate) within :data:`KS_BOUNDS`; the
    variable is named ``"ks"``.
    """
    measured = paper_measurements() if measured is None else measured
    start = ks_estimate(params)[0] if initial is None else float(initial)
    return calibrate(
        lambda ks: reference_bridge("M1", ks=ks, params=params),
        measured,
        {"ks": (start, *KS_BOUNDS)},
        by=by,
        observation=deck_observation(params),
        n_modes=n_modes,
    )


def tuned_bridge(ks: float, params: BridgeParameters = BridgeParameters(), friction: float = FRICTION) -> Model:
    """Step 2: the M2 model, regularized Coulomb with stick stiffness ``ks`` and ``friction``."""
    return reference_bridge("M2", ks=ks, params=params, friction=friction)


def measured_damping(decrements=LOG_DECREMENTS, stated=DAMPING_RATIOS) -> dict:
    """Damping ratios from the measured ``(frequency, log decrement)`` pairs and Rayleigh through the first two.

    ``rayleigh`` uses the ratios computed from the decrements (2.07 % and 2.70 %);
    ``rayleigh_paper_ratios`` the ratios as the paper states them (``stated``: 2.1 % and 2.7 %),
    which give its alpha = 0.21 1/s and beta = 0.00208 s.
    """
    ratios = [(f, damping_ratio_from_log_decrement(d)) for f, d in decrements]

    def rayleigh(pairs):
        (f1, z1), (f2, z2) = pairs[:2]
        alpha, beta = rayleigh_from_ratios(f1, z1, f2, z2)
        return {"alpha": alpha, "beta": beta}

    return {
        "decrements": [{"frequency": f, "decrement": d} for f, d in decrements],
        "ratios": [{"frequency": f, "ratio": z} for f, z in ratios],
        "rayleigh": rayleigh(ratios),
        "rayleigh_paper_ratios": rayleigh(list(stated)),
    }
