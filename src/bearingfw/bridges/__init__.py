"""The paper's reference bridge: a five-span RC arch bridge on pot bearings, as a bearingfw model.

``reference_bridge(preset, ks, params)`` builds it with one of the paper's bearing models
(:data:`PRESETS`: ``M0``, ``M1``, ``M2``, ``fixed``, ``bouc-wen``). The geometry and every
assumption the paper does not state are the fields of :class:`BridgeParameters`; the numbers
the paper states are in :mod:`bearingfw.bridges.paper`; the bearing layout in
:mod:`bearingfw.bridges.layout`. The paper's tuning study on this bridge (step 1, step 2,
damping) is :mod:`bearingfw.bridges.study`, and the offline fit of the calibrated defaults
``python -m bearingfw.bridges.calibrate_defaults``.
"""

from bearingfw.bridges import paper
from bearingfw.bridges.layout import ABUTMENT_AXES, AXES, BEARINGS, FIXED_AXIS, PILLAR_AXES, BearingSpec
from bearingfw.bridges.parameters import CALIBRATED, BridgeParameters
from bearingfw.bridges.presets import (
    DEFAULT_KS,
    PRESETS,
    Preset,
    bearing_laws,
    dead_load_normal_forces,
    reference_bridge,
)
from bearingfw.bridges.reference import (
    DECK_COMPONENTS,
    DECK_SHARE,
    RESPONSE_ELEMENTS,
    Grid,
    bearing_offset,
    bridge_model,
    deck_nodes,
    grid,
)

__all__ = [
    "ABUTMENT_AXES",
    "AXES",
    "BEARINGS",
    "CALIBRATED",
    "DECK_COMPONENTS",
    "DECK_SHARE",
    "DEFAULT_KS",
    "FIXED_AXIS",
    "PILLAR_AXES",
    "PRESETS",
    "RESPONSE_ELEMENTS",
    "BearingSpec",
    "BridgeParameters",
    "Grid",
    "Preset",
    "bearing_laws",
    "bearing_offset",
    "bridge_model",
    "dead_load_normal_forces",
    "deck_nodes",
    "grid",
    "paper",
    "reference_bridge",
]
