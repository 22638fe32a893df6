"""The module the ``bearingfw`` entry point names: bearingfw registers it with pluggy and calls its hooks."""

import bearingfw

from bearingfw_elastomeric.law import ElastomericPlasticity, lead_rubber_parameters

#: The preset's design choices (see :func:`preset_law` and the README).
PRESET_PERIOD = 2.5  # s: isolated period of the mass each bearing carries, from K_d
PRESET_STRENGTH_RATIO = 0.05  # qd / W
PRESET_STIFFNESS_RATIO = 10.0  # K_u / K_d, i.e. alpha = 0.1


def preset_law(bearing: bearingfw.PresetBearing) -> tuple[str, dict]:
    """Each sliding bearing of the reference bridge replaced by a lead-rubber bearing designed for
    its dead load W: ``qd = 0.05 W``, ``K_d = W (2 pi / 2.5 s)^2 / g``, ``k = 10 K_d``
    (:func:`lead_rubber_parameters`). K_s and mu play no part."""
    weight = bearing.dead_load
    if weight is None or not weight > 0:
        raise bearingfw.ParameterError(
            f"preset 'lead-rubber': bearing {bearing.name!r} carries N = {weight!r} N at dead load; "
            "a lead-rubber bearing is designed for the weight it carries, which must be > 0"
        )
    params = lead_rubber_parameters(
        weight, period=PRESET_PERIOD, strength_ratio=PRESET_STRENGTH_RATIO, stiffness_ratio=PRESET_STIFFNESS_RATIO
    )
    return (ElastomericPlasticity.name, params)


@bearingfw.hookimpl
def bearingfw_register_laws():
    return [ElastomericPlasticity]


@bearingfw.hookimpl
def bearingfw_register_presets():
    return [
        bearingfw.BearingPreset(
            name="lead-rubber",
            description="lead-rubber bearings designed for each bearing's dead load W: qd = 0.05 W, "
            "isolated period 2.5 s (K_d), K_u = 10 K_d",
            law=preset_law,
            needs_dead_load=True,
        )
    ]
