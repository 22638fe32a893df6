"""The numbers the paper states about its bridge and its tuning (section 2.2, 3.1-3.4).

They are data, not assumptions: the assumptions (everything the paper does not state) are
the fields of :class:`bearingfw.bridges.BridgeParameters`. Frequencies are in Hz, stiffnesses
in N/m, forces in N. Modes are named ``"<label> <k>"`` after the kernel's labels
(:data:`bearingfw.analysis.LABELS`): ``"vertical 1"`` is the first mode labelled vertical.
"""

from __future__ import annotations

__all__ = [
    "BEARING_CAPACITY",
    "DAMPING_RATIOS",
    "FIXED_F1",
    "FRICTION",
    "HANGERS",
    "KS_EQ11",
    "KS_FIT",
    "LENGTH",
    "LOG_DECREMENTS",
    "MODES",
    "PILLAR_HEIGHT",
    "PILLAR_SIDE",
    "PILLAR_STIFFNESS",
    "RAYLEIGH",
    "TABLE2_FE",
    "TABLE2_OMA",
    "TABLE3_TUNED",
    "TENDON_AREA",
]

#: Table 2's modes, in the paper's order.
MODES = ("vertical 1", "lateral 1", "vertical 2", "torsional 1")
#: Table 2, FE model no. 1 (frictionless sliding, "untuned").
TABLE2_FE = {"vertical 1": 1.57, "lateral 1": 1.87, "vertical 2": 3.48, "torsional 1": 14.30}
#: Table 2, operational modal analysis (SSI) of the bridge.
TABLE2_OMA = {"vertical 1": 1.50, "lateral 1": 2.48, "vertical 2": 3.36, "torsional 1": 14.26}
#: Table 3: the model tuned with K_s = 400 MN/m springs on the sliding directions.
TABLE3_TUNED = {"vertical 1": 1.60, "lateral 1": 2.30, "vertical 2": 3.48, "torsional 1": 14.31}
#: Section 3.3: every bearing fixed lifts the first vertical frequency to 1.90 Hz.
FIXED_F1 = 1.90
#: Section 3.3: bending stiffness of one pillar, K_c = 3 E I / h^3 (eq. 7).
PILLAR_STIFFNESS = 147e6
#: Section 3.3: eq. 11 with K_c, f_a = 1.87 Hz and f_b = 2.48 Hz.
KS_EQ11 = 462e6
#: Section 3.3: the least-squares stick stiffness of the paper's model.
KS_FIT = 400e6
#: Section 3.4: friction coefficient of the PTFE-steel sliding surfaces (design range 0.03-0.06).
FRICTION = 0.04
#: Section 3.2: logarithmic decrements of the first and second vertical modes at their OMA frequencies.
LOG_DECREMENTS = ((1.50, 0.13), (3.36, 0.17))
#: Section 3.2: the damping ratios from those decrements.
DAMPING_RATIOS = ((1.50, 0.021), (3.36, 0.027))
#: Section 3.2: Rayleigh coefficients (alpha in 1/s, beta in s).
RAYLEIGH = (0.21, 0.00208)
#: Section 2.2.1: prestressing tendons per girder (m^2), steel Y1860.
TENDON_AREA = 150e-4
#: Section 2.2.1: pillars (m).
PILLAR_HEIGHT = 5.9
PILLAR_SIDE = 1.4
#: Section 2.2.1: characteristic bearing capacities per axis 1..6 (N).
BEARING_CAPACITY = {1: 1500e3, 2: 3600e3, 3: 3250e3, 4: 3250e3, 5: 3600e3, 6: 1500e3}
#: Section 2.2.1: hangers in total (two arches).
HANGERS = 28
#: Section 1: total length (m).
LENGTH = 160.0
