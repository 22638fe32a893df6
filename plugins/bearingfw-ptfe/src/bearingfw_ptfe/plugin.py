"""The module the ``bearingfw`` entry point names: bearingfw registers it with pluggy and calls its hooks."""

from __future__ import annotations

import math

import bearingfw

from bearingfw_ptfe.law import PTFEFriction

#: Contact pressure of a sliding bearing's PTFE disc under the dead load (Pa), the preset's design value.
DEAD_LOAD_PRESSURE = 30e6
#: f_min = STATIC_RATIO * f_max: the coefficient at rest against the one at sliding speed.
STATIC_RATIO = 0.5
#: Transition rate a (s/m): above 0.1 m/s, f_max - mu is at most exp(-2.5) = 8.2 % of f_max - f_min.
TRANSITION_RATE = 25.0
#: delta_mu = PRESSURE_DROP * mu, with alpha = 1 / DEAD_LOAD_PRESSURE.
PRESSURE_DROP = 0.25


def ptfe_preset_law(bearing: bearingfw.PresetBearing) -> tuple[str, dict]:
    """The ``ptfe`` preset's law of one sliding bearing (see README, "Preset").

    At the dead-load pressure and high speed the coefficient is the bearing's ``friction`` (the
    paper's 0.04); at rest it is half that; more pressure lowers it, less raises it.
    """
    normal = bearing.dead_load
    if normal is None or not normal > 0:
        raise bearingfw.ParameterError(
            f"ptfe preset: bearing {bearing.name!r} carries N = {normal!r} N at dead load; the preset sizes the "
            f"PTFE disc from it and needs N > 0"
        )
    mu = float(bearing.friction)
    alpha = 1.0 / DEAD_LOAD_PRESSURE
    delta_mu = PRESSURE_DROP * mu
    # f_max(p) = f_max0 - delta_mu tanh(alpha p) equals mu at the dead-load pressure (alpha p = 1).
    f_max0 = mu + delta_mu * math.tanh(1.0)
    return (
        PTFEFriction.name,
        {
            "k": float(bearing.ks),
            "f_min": STATIC_RATIO * mu,
            "f_max": f_max0,
            "a": TRANSITION_RATE,
            "area": normal / DEAD_LOAD_PRESSURE,
            "delta_mu": delta_mu,
            "alpha": alpha,
        },
    )


@bearingfw.hookimpl
def bearingfw_register_laws():
    return [PTFEFriction]


@bearingfw.hookimpl
def bearingfw_register_presets():
    return [
        bearingfw.BearingPreset(
            name="ptfe",
            description="PTFE friction k = K_s, mu(v, p): mu at speed and dead-load pressure, mu/2 at rest",
            law=ptfe_preset_law,
            needs_dead_load=True,
        )
    ]
