"""The paper's comparative study (section 4.1, figures 18-21) as an experiment definition: data only.

Everything the study owes to the paper is here and nowhere in the experiment engine: its bearing
models M0, M1, M2, fixed and Bouc-Wen, the response points S1 (mid main span) and 3B (over a
sliding bearing), the reference model M2, the friction coefficient 0.04 (through the presets'
default), the paper's measured damping, the table and figures it shows, and its findings, stated
as ``[[findings]]`` and checked like any user's. ``bearingfw run`` without a file runs it
(:data:`STUDY_TOML`, printed by ``bearingfw run --print-default``).

The findings (the bearingfw design notes' testable form of the paper's statements):

1. D_0: M1 and M2 within 15 % of each other at S1 and at 3B (the bearings stick);
2. D_0: M0 below 0.7 x M1 at S1 and below 0.3 x M1 at 3B (the paper: about a half, a tenth);
3. the M0/M1 ratios equal under D_0 and D_II (both models linear);
4. D_II: M2 at 3B below 0.7 x M1 (friction caps the force the girder gets);
5. M2's maximum friction ratio abs(F)/N at 3B equals mu under D_II, D_III and D_IV (it slides).

The paper's linearity argument (3) holds for the dynamic part of the stress (the total adds the
same dead-load stress at every intensity), so the stress findings are stated on the
``stress_dynamic`` family; the same checks on the totals (``stress``) are a second group, for
comparison. A string constant rather than a data file, so that every kind of install has it.

K_s of M1, M2 and Bouc-Wen is the presets' default, :data:`bearingfw.bridges.DEFAULT_KS`
(400 MN/m); the description states it with :data:`bearingfw.bridges.KS_SOURCE`, so the report
says where it comes from. Where each finding holds on this bridge (other tremor seeds, real
records) and why: ``examples/paper-study/README.md``.
"""

from __future__ import annotations

import textwrap

from bearingfw.bridges.presets import DEFAULT_KS, KS_SOURCE

__all__ = ["STUDY_TOML"]

_FINDINGS = "The paper's findings (dynamic stresses; friction ratio at 3B)"
_TOTALS = "The same stress checks on the total stresses (dead load + tremor), for comparison"


def _stress_findings(family: str, group: str, friction: bool) -> str:
    lines = []

    def finding(**fields):
        lines.append("[[findings]]")
        lines.extend(f"{key} = {value}" for key, value in fields.items())
        lines.append(f'group = "{group}"')
        lines.append("")

    for where in ("S1", "3B"):
        finding(name=f'"D_0, {where}: M1 and M2 within 15 %"', metric=f'"{family}.{where}"', level='"D_0"',
                models='["M2", "M1"]', within="0.15")
    for where, bound in (("S1", "0.7"), ("3B", "0.3")):
        finding(name=f'"D_0, {where}: M0 below {bound} x M1"', metric=f'"{family}.{where}"', level='"D_0"',
                models='["M0", "M1"]', below=bound)
    for where in ("S1", "3B"):
        finding(name=f'"{where}: M0/M1 the same under D_0 and D_II (linear models)"', metric=f'"{family}.{where}"',
                level='["D_0", "D_II"]', models='["M0", "M1"]', same="1e-6")
    finding(name='"D_II, 3B: M2 below 0.7 x M1"', metric=f'"{family}.3B"', level='"D_II"', models='["M2", "M1"]',
            below="0.7")
    if friction:
        finding(name="\"{level}: M2's maximum friction ratio at 3B equals mu = 0.04\"", metric='"friction_ratio.3B"',
                level='["D_II", "D_III", "D_IV"]', model='"M2"', equals="0.04", tolerance="1e-6")
    return "\n".join(lines)


#: The K_s of M1, M2 and Bouc-Wen and where it comes from, as the report's description states it.
_KS = " \\\n".join(textwrap.wrap(f"K_s = {DEFAULT_KS:g} N/m ({DEFAULT_KS / 1e6:.0f} MN/m): {KS_SOURCE}.", 100))

#: The study, as ``bearingfw run --print-default`` prints it.
STUDY_TOML = '''\
# bearingfw experiment: the comparative study of the paper (section 4.1, figures 18-21) on the
# reference bridge. `bearingfw run` runs it when given no file; copy it to start your own.
# Units SI (N, m, s). Every key is optional unless marked; a key left out takes the default shown.

name = "paper-study"                    # required; names the output folder bearingfw-results/<name>
description = """The paper's comparative study: sliding bearings modelled as frictionless (M0), \\
linear springs K_s (M1), regularized Coulomb friction with K_s and mu = 0.04 (M2), fixed, and \\
Bouc-Wen, under the synthetic mining tremor scaled to the intensity levels D_0 .. D_IV. \\
''' + _KS + '''"""
reference = "M2"                        # the model the ratio matrices divide by (default: the first)
# plugins = ["my_laws"]                 # modules with bearingfw hook implementations (laws, readers,
#                                       # scales, presets, metric families, executors) to load
# python_path = ["."]                   # folders, relative to this file, where those modules and a
#                                       # structure builder are found (this file's folder always is)

[structure]
builder = "reference"                   # the paper's bridge, or "package.module:function" or
                                        # "path/to/file.py:function" returning a bearingfw.model.Model
                                        # (called with `options` as keywords; `bearingfw run
                                        # --structure SPEC --option key=value` overrides both)
# options = { element_length = 2.5 }    # reference: fields of bearingfw.bridges.BridgeParameters
elements = ["S1", "S2", "2A", "3A", "4A", "5A", "2B", "3B", "4B", "5B"]   # stress metrics (default none)
deck_nodes = ["GA4", "GB4", "GA12", "GB12", "GA32", "GB32", "GA51", "GB51", "GA60", "GB60"]
                                        # accelerations (here both girders at every mid-span; default none)
mode_labels = "bearingfw.bridges.study:mode_labels"   # "deck lateral 1", "arches lateral 1": whose mode
# bearings = [...]                      # the connectors the models govern (default: every connector
#                                       # that is not JOIN; the reference bridge applies presets itself)

# Bearing models: the law of the sliding directions of every sliding bearing. Either a preset
# (`bearingfw plugins` lists them: M0, M1, M2, fixed, bouc-wen; with optional ks = stick stiffness
# K_s in N/m, default 4e8: `bearingfw tune`'s step 1, bounded as the paper's; friction = mu,
# default 0.04) or any registered law:
#   [models.soft-friction]
#   law = "regularized-coulomb"
#   params = { k = 2e8, mu = 0.03 }
[models.M0]
preset = "M0"                           # frictionless sliding: the untuned model
[models.M1]
preset = "M1"                           # linear springs k = K_s: step 1 of the tuning
[models.M2]
preset = "M2"                           # regularized Coulomb, k = K_s, mu = 0.04: step 2
[models.fixed]
preset = "fixed"                        # every bearing fixed
[models.bouc-wen]
preset = "bouc-wen"                     # smooth hysteresis saturating at mu N_dead
friction = 0.04                         # its mu (the default), stated for the friction-ratio figure's line

# Ground motion, the same at every support. One of:
# - `seed`: the synthetic mining tremor (labelled synthetic everywhere; `tremor = { ... }` sets
#   fields of bearingfw.motion.TremorParameters);
# - `x`, `y`, `z` (any subset): the file acting in each global direction (relative to this file;
#   "FILE#2" is the 2nd component of a multi-component file, "-FILE" flips it); a file judged
#   vertical is refused for x or y unless `vertical_as_horizontal = true`;
# - `files = ["h1", "h2", "v"]` with `components`: the record component applied in global x (along
#   the bridge), y (across) and z (up): h1, h2, v, a minus sign to flip one, "0" to leave one out.
# `format`, `dt`, `units` describe files that do not state them.
[records.tremor]
seed = 0                                # W-E (h1), N-S (h2), Z (v); 16 s at dt = 0.005 s
components = ["h1", "h2", "v"]          # the paper does not orient the bridge: W-E along it

[intensities]
levels = ["D_0", "D_I", "D_II", "D_III", "D_IV"]   # PGA_H10 0.10, 0.23, 0.46, 0.75, 1.10 m/s^2;
                                        # "as-recorded" runs the record unscaled
# values = { D_II = 0.5 }               # change the PGA_H10 (m/s^2) of some levels
# pga_h10 = [0.1, 0.46]                 # PGA_H10 values (m/s^2), besides or instead of levels
# pga = [1.0, 2.0]                      # peak horizontal ground acceleration (m/s^2)
# sa = [2.0, 4.0]                       # Sa(T, 5 %) (m/s^2) at `period` (s, or "T1": the first mode of
# period = "T1"                         # the structure as its builder returns it)
# scale = "usb-pga-h10"                 # the intensity scale a level's degree is checked on

[integration]                           # bearingfw.analysis.TransientSettings
alpha = -0.05                           # HHT alpha (0: no numerical dissipation)
dt_integration = 0.005                  # s; divides the record's time step (else the record is resampled)
# tol_force = 1e-8, tol_displacement = 1e-10, max_iterations = 25, max_halvings = 6, path = "fast"

[damping]                               # Rayleigh, from two (frequency Hz, ratio) pairs ...
ratios = [[1.50, 0.021], [3.36, 0.027]] # the paper's measured damping (log decrements 0.13, 0.17)
# alpha = 0.21                          # ... or the coefficients (1/s, s)
# beta = 0.00208
# ratio = 0.02                          # ... or one ratio at the structure's first two natural
#                                       # frequencies (the default when [damping] is left out)

[output]
table = ["stress.S1", "stress.3B", "stress_dynamic.S1", "stress_dynamic.3B",
         "bearing_force.3B", "slip.3B", "friction_ratio.3B", "deck_acceleration.y"]
                                        # default: every family's items the structure has
aggregate = "ec8"                       # several records: mean of >= 7, else max ("max", "mean")
histories = true                        # keep each cell's time histories (NPZ; the figures need them)
every = 1                               # keep every k-th integration step in them (the metrics use all);
                                        # changing either computes no cell again, except where finer
                                        # histories than the stored ones are asked for
report = true                           # write report.md

[figures]
draw = "report"                         # report | all | none; formats = ["png"] (also "svg", "pdf")
# intensities = ["D_0", "D_II"]         # default: all
elements = ["S1", "3B"]                 # stress histories (figures 18 and 20)
bearing = "3B"                          # its force and friction ratio (figures 19 and 21)
compare = ["M0", "M1", "M2"]            # the models of figures 18-21 (default: all); M2 drawn on top
hysteresis = true                       # force-displacement loops of every bearing (with draw = "all")

# Findings: statements checked on the matrices and reported with what they measured. Each names a
# metric ("family.item"), a level (or a list: the statement for each), `models = [A, B]` (the
# ratio A/B) or `model = A` (its value, SI units), and one test: within = t (abs(x - 1) <= t),
# below = b, above = a, equals = e (with tolerance, relative), or same = t (x the same at every
# level of the list). `name` is the statement ("{level}" stands for the level), `group` its heading.

''' + _stress_findings("stress_dynamic", _FINDINGS, friction=True) + "\n" + _stress_findings(
    "stress", _TOTALS, friction=False)
