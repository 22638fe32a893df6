"""The module the ``bearingfw`` entry point names: bearingfw registers it with pluggy and calls its hooks.

It contributes the law ``bouc-wen`` and the bridge preset ``bouc-wen``: Bouc-Wen as friction.
With ``alpha = 0`` and ``A = 1`` the force is ``k uy z`` with ``|z| <= 1`` (``beta + gamma = 1``),
so the stiffness is ``K_s`` at first and the force saturates at ``k uy = mu N_dead``, the
friction force at dead load, reached smoothly (``beta = gamma`` unloads along the initial
stiffness, like the stick branch). Unlike M2 it does not follow the normal force in time:
``N_dead`` is each bearing's dead-load normal force, which the bridge builder computes once.

The exponent. The registered preset uses ``n = 2``, Park, Wen & Ang's biaxial exponent, which the
law integrates exactly, in closed form (a time history costs about twice M2's; ``n = 4`` needs
backward-Euler substeps, about 40 times slower). From rest the force reaches 76 % of
``mu N_dead`` at ``u = uy``, 96 % at ``2 uy`` and 99.5 % at ``3 uy`` (``tanh``). For another
smoothness build the preset yourself and pass it where a preset name goes::

    from bearingfw.bridges import reference_bridge
    from bearingfw_boucwen.plugin import bouc_wen_preset

    model = reference_bridge(bouc_wen_preset(exponent=4.0))
"""

import bearingfw

from bearingfw_boucwen.law import BoucWen

__all__ = ["bouc_wen_preset"]


def bouc_wen_preset(exponent: float = 2.0) -> bearingfw.BearingPreset:
    """The ``bouc-wen`` bridge preset with the smoothness exponent ``n = exponent`` (module docstring)."""
    # The law's own field checks the exponent now, rather than when the bridge is built.
    BoucWen(k=1.0, alpha=0.0, uy=1.0, n=exponent)
    exponent = float(exponent)

    def law(bearing: bearingfw.PresetBearing):
        if not bearing.friction > 0:
            raise bearingfw.ParameterError(
                f"bouc-wen preset: friction = {bearing.friction!r} leaves no saturation force mu N_dead; it needs "
                f"0 < friction < 1"
            )
        normal = bearing.dead_load
        if normal is None or not normal > 0:
            raise bearingfw.ParameterError(
                f"bouc-wen preset: bearing {bearing.name!r} carries N = {normal!r} N at dead load; it needs N > 0"
            )
        # saturation force (1 - alpha) k uy z_max = k uy = mu N_dead (z_max = 1 for A = beta + gamma = 1)
        return ("bouc-wen", {"k": bearing.ks, "alpha": 0.0, "uy": bearing.friction * normal / bearing.ks, "A": 1.0,
                             "beta": 0.5, "gamma": 0.5, "n": exponent})

    return bearingfw.BearingPreset(
        "bouc-wen", f"Bouc-Wen k = K_s saturating at mu N_dead (n = {exponent:g})", law, needs_dead_load=True
    )


@bearingfw.hookimpl
def bearingfw_register_laws():
    return [BoucWen]


@bearingfw.hookimpl
def bearingfw_register_presets():
    return [bouc_wen_preset()]
