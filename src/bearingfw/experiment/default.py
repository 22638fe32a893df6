"""The built-in experiment: the paper's comparative study, run by ``bearingfw run`` without a file.

A string constant rather than a data file, so that every kind of install (wheel, sdist,
editable) has it. ``bearingfw run --print-default`` prints it as a starting point for one's own
experiment; :func:`default_experiment` loads it.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["DEFAULT_TABLE", "DEFAULT_TOML", "default_experiment"]

#: The metrics printed and shown in the report when ``[output] table`` is not given (those that
#: exist in the experiment): the paper's response points S1 and 3B.
DEFAULT_TABLE = (
    "stress.S1",
    "stress.3B",
    "stress_dynamic.S1",
    "stress_dynamic.3B",
    "bearing_force.3B",
    "slip.3B",
    "friction_ratio.3B",
    "deck_acceleration.y",
)

DEFAULT_TOML = '''\
# bearingfw experiment: the comparative study of the paper (section 4.1, figures 18-21) on the
# reference bridge. `bearingfw run` runs it when given no file; copy it to start your own.
# Units SI (N, m, s). Every key is optional unless marked; a key left out takes the default shown.

name = "paper-study"                    # required; names the output folder bearingfw-results/<name>
description = """The paper's comparative study: sliding bearings modelled as frictionless (M0), \\
linear springs K_s (M1), regularized Coulomb friction with K_s and mu = 0.04 (M2), fixed, and \\
Bouc-Wen, under the synthetic mining tremor scaled to the intensity levels D_0 .. D_IV."""
reference = "M2"                        # the model the ratio matrices divide by
# plugins = ["my_laws"]                 # modules with bearingfw hook implementations (laws, readers,
#                                       # scales) to load besides the installed plugins
# python_path = ["."]                   # folders, relative to this file, where those modules and a
#                                       # structure builder are found (this file's folder always is)

[structure]
builder = "reference"                   # the paper's bridge, or "package.module:function" returning a
                                        # bearingfw.model.Model (called with `options` as keywords)
# options = { element_length = 2.5 }    # reference: fields of bearingfw.bridges.BridgeParameters
# elements = ["S1", "S2", "2A", "3A", "4A", "5A", "2B", "3B", "4B", "5B"]   # stress metrics
# deck_nodes = [...]                    # accelerations (reference: both girders at every mid-span)
# bearings = [...]                      # user builders: the connectors the models govern
#                                       # (default: every connector that is not JOIN)

# Bearing models: the law of the sliding directions of every sliding bearing. Either a preset
# of bearingfw.bridges (M0, M1, M2, fixed, bouc-wen; with optional ks = stick stiffness K_s in
# N/m, default 4e8, and friction = mu, default 0.04) or any registered law:
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

# Ground motion, the same at every support. Either `seed`: the synthetic mining tremor (labelled
# synthetic everywhere; `tremor = { ... }` sets fields of bearingfw.motion.TremorParameters), or
# `files = ["h1", "h2", "v"]` (relative to this file; `format`, `dt`, `units` for files that do
# not state them). `components` gives the record component applied in global x (along the
# bridge), y (across) and z (up): h1, h2, v, a minus sign to flip one, "0" to leave a direction out.
[records.tremor]
seed = 0                                # W-E (h1), N-S (h2), Z (v); 16 s at dt = 0.005 s
components = ["h1", "h2", "v"]          # the paper does not orient the bridge: W-E along it

[intensities]
levels = ["D_0", "D_I", "D_II", "D_III", "D_IV"]   # PGA_H10 0.10, 0.23, 0.46, 0.75, 1.10 m/s^2
# values = { D_II = 0.5 }               # change the PGA_H10 (m/s^2) of some levels
# pga_h10 = [0.1, 0.46]                 # or plain PGA_H10 values instead of levels
# scale = "usb-pga-h10"                 # the intensity scale a level's degree is checked on

[integration]                           # bearingfw.analysis.TransientSettings
alpha = -0.05                           # HHT alpha (0: no numerical dissipation)
dt_integration = 0.005                  # s; divides the record's time step (else the record is resampled)
# tol_force = 1e-8, tol_displacement = 1e-10, max_iterations = 25, max_halvings = 6, path = "fast"

[damping]                               # Rayleigh, from two (frequency Hz, ratio) pairs ...
ratios = [[1.50, 0.021], [3.36, 0.027]] # the paper's measured damping (log decrements 0.13, 0.17)
# alpha = 0.21                          # ... or the coefficients (1/s, s)
# beta = 0.00208

[output]
table = ["stress.S1", "stress.3B", "stress_dynamic.S1", "stress_dynamic.3B",
         "bearing_force.3B", "slip.3B", "friction_ratio.3B", "deck_acceleration.y"]
aggregate = "ec8"                       # several records: mean of >= 7, else max ("max", "mean")
histories = true                        # keep each cell's time histories (NPZ; the figures need them)
every = 1                               # keep every k-th integration step in them (the metrics use all);
                                        # changing either computes no cell again, except where finer
                                        # histories than the stored ones are asked for
report = true                           # write report.md

[figures]
draw = true
# intensities = ["D_0", "D_II"]         # default: all
elements = ["S1", "3B"]                 # stress histories of all models (figures 18 and 20)
bearing = "3B"                          # its force and friction ratio (figures 19 and 21)
compare = ["M1", "M2"]                  # models in the bearing-force figure
hysteresis = true                       # force-displacement loops of every bearing
'''


def default_experiment(base_dir: str | Path | None = None):
    """The built-in experiment (:data:`DEFAULT_TOML`) as an :class:`~bearingfw.experiment.spec.Experiment`."""
    from bearingfw.experiment.spec import parse_experiment

    return parse_experiment(DEFAULT_TOML, base_dir, origin="<built-in experiment>")
