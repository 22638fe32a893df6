"""The module the ``bearingfw`` entry point names: bearingfw registers it with pluggy and calls its hooks."""

from __future__ import annotations

import math

import bearingfw

from bearingfw_pendulum.law import FrictionPendulum, VelocityFrictionPendulum

#: The isolation period 2 pi sqrt(R / g) of the preset's pendulum (s): a common design value.
ISOLATION_PERIOD = 3.0
#: Its effective radius (m): R = g (T / 2 pi)^2 = 2.24 m.
PRESET_RADIUS = 9.81 * (ISOLATION_PERIOD / (2.0 * math.pi)) ** 2


def pendulum_preset_law(bearing: bearingfw.PresetBearing) -> tuple[str, dict]:
    """The ``pendulum`` preset's law of one sliding bearing (see README, "Preset")."""
    return (
        FrictionPendulum.name,
        {"k": float(bearing.ks), "R": PRESET_RADIUS, "mu": float(bearing.friction)},
    )


@bearingfw.hookimpl
def bearingfw_register_laws():
    return [FrictionPendulum, VelocityFrictionPendulum]


@bearingfw.hookimpl
def bearingfw_register_presets():
    return [
        bearingfw.BearingPreset(
            name="pendulum",
            description="single friction pendulum R = 2.24 m (T = 3 s), k = K_s, mu",
            law=pendulum_preset_law,
        )
    ]
