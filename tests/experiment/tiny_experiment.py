"""The tiny experiment of these tests: the example's two-span girder, a short synthetic tremor.

``tiny_toml(...)`` returns the TOML text; ``write_tiny(folder, ...)`` writes it as
``folder/tiny.toml``. The structure is ``examples/small-bridge/small_bridge.py`` (so the tests
exercise the example), the test laws come from ``bfw_test_laws.py`` next to this file.
"""

from __future__ import annotations

from pathlib import Path

HERE = Path(__file__).resolve().parent
EXAMPLE = HERE.parents[1] / "examples" / "small-bridge"

#: A 10 s synthetic tremor at dt = 0.01 s (decay 2/s so that its tail fits), integrated at 0.01 s.
TINY = """\
name = "{name}"
python_path = ["{example}", "{here}"]
plugins = ["bfw_test_laws"]
{reference}

[structure]
builder = "small_bridge:build"
options = {{ elements_per_span = 4 }}
elements = ["G2", "G4"]
deck_nodes = ["G2", "G6"]

{models}

[records.tremor]
seed = 1
tremor = {{ duration = 10.0, dt = 0.01, decay = 2.0 }}

[intensities]
levels = {levels}

[integration]
dt_integration = 0.01

[output]
table = ["stress.G4", "stress_dynamic.G4", "bearing_force.1B", "friction_ratio.1B", "deck_acceleration.y"]

[figures]
draw = {figures}
elements = ["G2", "G4"]
bearing = "1B"
{compare}
{extra}
"""

MODELS = {
    "M0": '[models.M0]\npreset = "M0"',
    "M1": '[models.M1]\npreset = "M1"',
    "M2": '[models.M2]\npreset = "M2"',
    "boom": '[models.boom]\nlaw = "test-exploding-spring"',
    "slow": '[models.slow]\nlaw = "test-slow-spring"\nparams = {{ delay = {delay} }}',
    "held": '[models.held]\nlaw = "test-held-spring"',
    "block": '[models.block]\nlaw = "test-blocking-spring"',
    "mutate": '[models.mutate]\nlaw = "test-mutating-spring"',
    "noisy": '[models.noisy]\nlaw = "test-noisy-spring"',
    "deaf": '[models.deaf]\nlaw = "test-deaf-spring"',
}


def tiny_toml(models=("M0", "M1", "M2"), levels=("D_0", "D_II"), figures=False, name="tiny", extra="",
              delay=2e-4, **replace) -> str:
    compared = [m for m in ("M1", "M2") if m in models]
    text = TINY.format(
        name=name, example=EXAMPLE.as_posix(), here=HERE.as_posix(),
        reference='reference = "M1"' if "M1" in models else "",
        compare=f"compare = {compared!r}".replace("'", '"') if compared else "",
        models="\n".join(MODELS[m].format(delay=delay) for m in models),
        levels="[" + ", ".join(f'"{v}"' for v in levels) + "]",
        figures="true" if figures else "false", extra=extra,
    )
    for old, new in replace.items():
        text = text.replace(old, new)
    return text


def write_tiny(folder: Path, **kwargs) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "tiny.toml"
    path.write_text(tiny_toml(**kwargs))
    return path
