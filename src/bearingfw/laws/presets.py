"""The built-in bearing presets, registered through the ``bearingfw`` entry point like any plugin.

A preset says how the sliding directions of a bridge's sliding bearings are modelled (a bridge
built from presets keeps its JOIN bearings fixed and the tied directions of guided bearings tied):

=======  ====================  =============================================================
name     law                   sliding directions
=======  ====================  =============================================================
M0       frictionless          free sliding: the paper's untuned model
M1       linear-spring         ``k = K_s``: step 1 of the tuning (modal tuning)
M2       regularized-coulomb   ``k = K_s``, ``mu``: step 2, for time histories
fixed    (JOIN)                every bearing fixed (section 3.3's alternative)
=======  ====================  =============================================================

Law packages add their own (the bearingfw-boucwen package: ``bouc-wen``).
"""

from bearingfw.plugins.contracts import BearingPreset, PresetBearing
from bearingfw.plugins.hookspecs import hookimpl

__all__ = ["BUILTIN_PRESETS"]


def _frictionless(bearing: PresetBearing):
    return ("frictionless", {})


def _linear_spring(bearing: PresetBearing):
    return ("linear-spring", {"k": bearing.ks})


def _regularized_coulomb(bearing: PresetBearing):
    return ("regularized-coulomb", {"k": bearing.ks, "mu": bearing.friction})


def _fixed(bearing: PresetBearing):
    return None


BUILTIN_PRESETS = (
    BearingPreset("M0", "frictionless sliding (untuned)", _frictionless),
    BearingPreset("M1", "linear springs k = K_s (step 1)", _linear_spring),
    BearingPreset("M2", "regularized Coulomb k = K_s, mu (step 2)", _regularized_coulomb),
    BearingPreset("fixed", "every bearing fixed (JOIN)", _fixed),
)


@hookimpl
def bearingfw_register_presets():
    return list(BUILTIN_PRESETS)
