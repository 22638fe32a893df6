"""Every assumption of the reference bridge model, in one validated parameter object.

The paper (section 2.2) states the structural system, the materials, the tendon area, the
pillars, the number of hangers and the bearing layout; its figures with the spans and the
sections are missing. Every other number of the model is a field of :class:`BridgeParameters`,
with its unit, its allowed range and the reason for its default. Fields marked *calibrated*
were fitted once by ``python -m bearingfw.bridges.calibrate_defaults`` so that the untuned
model (frictionless sliding) reproduces the paper's Table 2; the others are engineering choices.

Concrete moduli are the EN 1992-1-1 mean secant values E_cm of the paper's classes; the
prestressed girders get the paper's eq. (1)::

    E_cs = (E_c A_c + E_s A_s) / (A_c + A_s)

with the girder line's concrete area A_c and 150 cm^2 of Y1860 tendons (E_s = 195 GPa).

Why these spans and arches. Table 2 has the second vertical mode at 2.2 times the first, with
no vertical mode between. The first vertical mode of an arch bridge is the antisymmetric one of
the arch span (two half-waves of girder and arch), the next the three-half-wave one; side spans
as long as those half-waves (a 60 m arch span between 30 m spans) would put their own modes
between. Side spans of 20 and 22.5 m around a 75 m arch span keep them above, and the total at
the bridge's 160 m; the 75 m span divides into the 15 hanger intervals of 5 m that 14 hangers
per arch need. Two half-waves against three of a beam are (3/2)^2 = 2.25 apart when its ends are
free to rotate, less when they are restrained: hinged springings and a steep, heavy arch bring
the ratio to about 2.06 here, the most this layout gives (calibrate_defaults).
"""

from __future__ import annotations

import numbers

import attrs

from bearingfw.bridges.paper import PILLAR_HEIGHT, PILLAR_SIDE, PILLAR_STIFFNESS, TENDON_AREA
from bearingfw.parameters import ParameterError, choice, integer_parameter, parameter

__all__ = ["CALIBRATED", "BridgeParameters"]

#: The fields fitted to Table 2 by :mod:`bearingfw.bridges.calibrate_defaults`.
CALIBRATED = ("superimposed_dead_load", "girder_depth", "arch_depth")


def _spans(value):
    try:
        return tuple(float(v) if isinstance(v, numbers.Real) and not isinstance(v, bool) else v for v in value)
    except TypeError:
        return value


def _check_flag(instance, attribute, value):
    if not isinstance(value, bool):
        raise ParameterError(f"BridgeParameters: field {attribute.name!r} must be true or false, got {value!r}")


def _check_spans(instance, attribute, value):
    ok = isinstance(value, tuple) and len(value) == 5 and all(isinstance(v, float) and v > 0 for v in value)
    if not ok:
        raise ParameterError(f"BridgeParameters: field 'spans' must be 5 span lengths > 0 (m), got {value!r}")


@attrs.frozen
class BridgeParameters:
    """Assumptions of the reference bridge (SI units; see the module docstring).

    Geometry: axis 1 at ``x = 0``; girder A runs at ``y = -girder_spacing / 2``, B at
    ``+girder_spacing / 2``; the girder axis (the T-section's centroid) is at ``z = 0``; the
    bearings' sliding surfaces are ``bearing_height`` below the soffit.
    """

    # --- layout ------------------------------------------------------------------------
    spans: tuple[float, ...] = attrs.field(
        default=(20.0, 22.5, 75.0, 22.5, 20.0),
        converter=_spans,
        validator=_check_spans,
        metadata={"unit": "m", "doc": "the five spans between axes 1..6 (160 m in all); the arches span the "
                  "third, the longest (module docstring)"},
    )
    element_length: float = parameter(
        low=0.5, high=10.0, default=2.5, unit="m",
        doc="girder element length; axes, hangers and crossbars fall on element ends (64 per girder)",
    )
    girder_spacing: float = parameter(
        low=2.0, high=20.0, default=7.0, unit="m", doc="between the axes of girders A and B"
    )
    # --- deck --------------------------------------------------------------------------
    deck_width: float = parameter(
        low=4.0, high=30.0, default=12.0, unit="m",
        doc="slab width (two traffic lanes and two sidewalks); each girder line carries half as its flange",
    )
    slab_thickness: float = parameter(low=0.1, high=1.0, default=0.25, unit="m", doc="deck slab")
    girder_width: float = parameter(low=0.2, high=4.0, default=1.0, unit="m", doc="girder web width")
    girder_depth: float = parameter(
        low=0.5, high=5.0, default=1.186, unit="m", doc="girder depth from the slab top to the soffit (calibrated)"
    )
    concrete_density: float = parameter(
        low=1500.0, high=3500.0, default=2500.0, unit="kg/m^3", doc="reinforced concrete"
    )
    concrete_poisson: float = parameter(low=0.0, high=0.5, default=0.2, doc="uncracked concrete (EN 1992-1-1)")
    girder_concrete_modulus: float = parameter(
        low=1e9, default=35e9, unit="Pa", doc="C40/50, E_cm (EN 1992-1-1); eq. 1 adds the tendons"
    )
    tendon_area: float = parameter(low=0.0, default=TENDON_AREA, unit="m^2", doc="per girder (paper: 150 cm^2)")
    tendon_modulus: float = parameter(low=1e9, default=195e9, unit="Pa", doc="Y1860 strand (EN 1992-1-1)")
    superimposed_dead_load: float = parameter(
        low=0.0, high=30000.0, default=2914.0, unit="kg/m",
        doc="non-structural mass per girder line: surfacing, sidewalks, barriers, services (calibrated)",
    )
    girder_torsion: float = parameter(
        low=1e-3, high=1000.0, default=300.0, unit="m^4",
        doc="effective St-Venant constant of one girder line, so that the deck is stiff in torsion between its "
        "bearings (Table 2's first torsional mode, 14.3 Hz, is far above what the open T's own constant, about "
        "0.5 m^4, would give: about 10 Hz); the deck then twists mainly by rocking on its bearing pairs",
    )
    crossbar_spacing: float = parameter(
        low=1.0, high=200.0, default=5.0, unit="m",
        doc="crossbars from axis 1 on at this spacing (and on every axis): under every hanger of the arch span; "
        "with the slab they keep the deck's cross-section rigid (bearingfw.bridges.reference), so only their "
        "mass is modelled",
    )
    crossbar_width: float = parameter(low=0.1, high=3.0, default=0.4, unit="m", doc="crossbar width (along x)")
    crossbar_depth: float = parameter(low=0.2, high=5.0, default=1.0, unit="m", doc="crossbar depth from the slab top")
    # --- bearings ----------------------------------------------------------------------
    bearing_height: float = parameter(
        low=0.0, high=2.0, default=0.2, unit="m",
        doc="soffit to the sliding surface: pot bearing with its plates (part of the rigid offset)",
    )
    bearing_vertical_stiffness: float = parameter(
        low=1e6, default=2.4e9, unit="N/m",
        doc="vertical stiffness of a sliding pot bearing (confined elastomer disc: a few GN/m, e.g. 3250 kN "
        "at 1.4 mm); it sets the deck's rocking on its bearing pairs, the torsional mode "
        "(bearingfw.bridges.calibrate_defaults)",
    )
    uplift: bool = attrs.field(
        default=False,
        validator=_check_flag,
        metadata={"doc": "the sliding bearings' vertical springs compression-only (a pot bearing lifts off instead "
                  "of pulling; bearingfw.model.Connector's uplift). Off by default: in the default study (M0, M1, M2 "
                  "at D_0..D_IV, synthetic tremor seed 0) no bearing lifts (the least normal force is 129 kN, M1 at "
                  "D_IV), while turning it on changes the dynamic stresses by up to 2.7 % and the deck's vertical "
                  "acceleration by up to 2.9 % through damping alone (Rayleigh's stiffness-proportional term does "
                  "not act on compression-only springs) at about 13 % more CPU time. Turn it on for vertical "
                  "shaking strong enough to unload a bearing"},
    )
    boucwen_exponent: float = parameter(
        low=1.0, default=2.0,
        doc="Bouc-Wen smoothness n of the 'bouc-wen' preset (larger: a sharper stick-slip knee; 2, Park-Wen-Ang's, "
        "is integrated in closed form, any other value by substeps, 20 to thousands of times slower)",
    )
    # --- pillars -----------------------------------------------------------------------
    pillar_height: float = parameter(low=0.5, default=PILLAR_HEIGHT, unit="m", doc="paper: 5.9 m")
    pillar_side: float = parameter(low=0.1, default=PILLAR_SIDE, unit="m", doc="square pillars, paper: 1.4 m")
    pillar_stiffness: float = parameter(
        low=0.0, low_open=True, default=PILLAR_STIFFNESS, unit="N/m",
        doc="K_c = 3 E I / h^3 of one pillar, a cantilever under a pinned bearing (paper, eq. 7: 147 MN/m); "
        "it sets the pillar modulus E = K_c h^3 / (3 I), 31.4 GPa, a little below C30/37's E_cm of 33 GPa",
    )
    pillar_elements: int = integer_parameter(low=1, high=10_000, default=4, doc="frame elements per pillar")
    # --- arches ------------------------------------------------------------------------
    arch_rise: float = parameter(
        low=1.0, high=40.0, default=19.5, unit="m",
        doc="rise of the parabolic arch axis above its springings (0.26 of the span: a steep arch, which with the "
        "hinges separates the first two vertical modes as far as Table 2 has them)",
    )
    arch_springing: float = parameter(
        low=-20.0, high=20.0, default=0.0, unit="m",
        doc="level of the springings relative to the bearings' sliding surfaces; the arches stand on the axis-3 "
        "and axis-4 foundations, independent of the deck, which hangs from them (so the arch span's weight "
        "bypasses bearings 3 and 4, whose capacity is below that of axes 2 and 5)",
    )
    arch_springings: str = choice(
        ("hinged", "clamped"),
        default="hinged",
        doc="the arches' springings: hinged about the transverse axis (a two-hinged arch, whose first two vertical "
        "modes are two and three half-waves far apart, as in Table 2) or clamped",
    )
    arch_width: float = parameter(low=0.2, high=5.0, default=1.7, unit="m", doc="arch rib width (transverse)")
    arch_depth: float = parameter(
        low=0.2, high=5.0, default=2.024, unit="m", doc="arch rib depth in its plane (calibrated)"
    )
    arch_wall: float = parameter(
        low=0.05, high=5.0, default=0.6, unit="m",
        doc="wall thickness of the arch ribs' box section (at least half the smaller side: solid); a hollow rib "
        "keeps the deck's share in the first vertical mode, which the arches dominate, visible to deck sensors",
    )
    arch_modulus: float = parameter(low=1e9, default=37e9, unit="Pa", doc="C50/60, E_cm (EN 1992-1-1)")
    bracing_struts: int = integer_parameter(
        low=0, high=10_000, default=5, doc="transverse struts between the arches at the hanger stations nearest the crown (wind bracing)"
    )
    strut_side: float = parameter(low=0.1, high=3.0, default=0.6, unit="m", doc="square concrete struts")
    bracing_diagonal_area: float = parameter(
        low=0.0, default=0.01, unit="m^2",
        doc="steel X-diagonals between consecutive struts (0: struts only); with them the arches form a "
        "laterally braced pair",
    )
    # --- hangers -----------------------------------------------------------------------
    hangers_per_arch: int = integer_parameter(
        low=1, high=10_000, default=14, doc="evenly spaced over the arch span (paper: 28 in all)"
    )
    hanger_diameter: float = parameter(low=0.01, high=0.5, default=0.075, unit="m", doc="solid S460 bars (trusses)")
    steel_modulus: float = parameter(low=1e9, default=210e9, unit="Pa", doc="S460 (EN 1993-1-1)")
    steel_density: float = parameter(low=1000.0, default=7850.0, unit="kg/m^3", doc="structural steel")
    steel_poisson: float = parameter(low=0.0, high=0.5, default=0.3, doc="structural steel (EN 1993-1-1)")

    # --- derived -----------------------------------------------------------------------
    @property
    def length(self) -> float:
        return float(sum(self.spans))

    @property
    def axis_positions(self) -> tuple[float, ...]:
        """x of axes 1..6 (m)."""
        xs = [0.0]
        for span in self.spans:
            xs.append(xs[-1] + span)
        return tuple(xs)

    @property
    def pillar_modulus(self) -> float:
        """The pillars' E from K_c = 3 E I / h^3 (eq. 7), I = side^4 / 12."""
        return self.pillar_stiffness * self.pillar_height**3 / (3 * self.pillar_side**4 / 12)
