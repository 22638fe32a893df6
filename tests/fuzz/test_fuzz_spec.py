"""Fuzzing experiment specs: hostile TOML built from the examples and the built-in study, with values of the
wrong type, out of range, NaN and infinities (as TOML numbers and as text), huge lists, unknown keys,
missing tables, unicode and deeply nested values.

Loading (:func:`bearingfw.experiment.spec.parse_experiment`, and :func:`load_experiment` for raw bytes)
either accepts a spec or raises :class:`~bearingfw.experiment.spec.SpecError` whose message starts with
the key path at fault; never another exception, never a hang. An unknown key outside the free-form
tables is always refused, naming it. A few cases go through ``bearingfw run`` as a user runs it: exit
status 2, one message naming the key, nothing written into the new output directory.
"""

from __future__ import annotations

import io
import json
import math
import re
import subprocess
import sys
import tomllib
from contextlib import redirect_stderr, redirect_stdout
from pathlib import Path

import attrs
import pytest
from fuzz_support import PROFILES, fuzz_settings, time_limit
from hypothesis import given, note
from hypothesis import strategies as st

from bearingfw.cli.main import main
from bearingfw.experiment import DEFAULT_TOML
from bearingfw.experiment.spec import Experiment, SpecError, load_experiment, parse_experiment

REPO = Path(__file__).resolve().parents[2]
#: The example experiments (TOML files with models; not a package's pyproject or a file of measured modes).
EXAMPLES = sorted(p for p in (REPO / "examples").rglob("*.toml") if "models" in tomllib.loads(p.read_text("utf-8")))
#: The valid specs the mutations start from: the built-in study and every example experiment.
SEEDS = {"<built-in>": DEFAULT_TOML, **{p.relative_to(REPO).as_posix(): p.read_text(encoding="utf-8") for p in EXAMPLES}}
#: Tables whose keys are the user's (a builder's options, a law's parameters ...), as key paths with ``*`` for
#: a name: any key is accepted there at load time and checked when the experiment runs.
FREE_FORM = [("structure", "options"), ("models", "*", "params"), ("records", "*", "tremor"), ("intensities", "values")]


def in_free_form(path) -> bool:
    """Whether the key path ``path`` lies inside one of the :data:`FREE_FORM` tables, or names a model or
    a record (``[models.<name>]``, ``[records.<name>]``: the user's names)."""
    if len(path) == 2 and path[0] in ("models", "records"):
        return True
    return any(len(path) > len(free) and all(f in ("*", p) for f, p in zip(free, path, strict=False))
               for free in FREE_FORM)
#: The top-level keys a message may start with (a field of the experiment), or TOML's own complaint.
TOP_LEVEL = {a.name for a in attrs.fields(Experiment)} - {"base_dir", "source"}
MESSAGE = re.compile(r"^(?P<key>[A-Za-z_]+)(\[\d+\])?([.:\[]|$)")


# -- a TOML writer for what the mutations produce ------------------------------------------------


def toml_string(text: str) -> str:
    """A TOML basic string: JSON's escapes are TOML's, but not its surrogate pairs (characters beyond
    the BMP stay literal) and TOML also forbids a literal DEL."""
    return json.dumps(text, ensure_ascii=False).replace("\x7f", "\\u007f")


def toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return toml_string(value)
    if isinstance(value, list | tuple):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{toml_string(str(k))} = {toml_value(v)}" for k, v in value.items()) + "}"
    raise TypeError(f"no TOML for {type(value).__name__}")


def toml_document(data: dict) -> str:
    """Top-level keys as ``key = value`` lines (tables inline): valid TOML for any nesting."""
    return "\n".join(f"{toml_string(str(k))} = {toml_value(v)}" for k, v in data.items()) + "\n"


# -- hostile values and mutations ------------------------------------------------------------------

numbers = st.sampled_from([0, -1, 1, 2**63 - 1, -(2**63), 0.0, -0.0, 1e-320, 1e300, -1e300, math.nan, math.inf,
                           -math.inf, 0.5, 1e6, 3])
nonfinite_text = st.sampled_from(["nan", "NaN", "inf", "-inf", "Infinity", "1e999", "", " ", "0x10", "1_0", "١"])
unicode_text = st.text(max_size=20)
leaf = st.one_of(numbers, nonfinite_text, unicode_text, st.booleans(), st.floats(allow_nan=True))
nested = st.recursive(leaf, lambda inner: st.one_of(st.lists(inner, max_size=3),
                                                    st.dictionaries(st.text(max_size=6), inner, max_size=3)),
                      max_leaves=12)


@st.composite
def deep(draw):
    depth = draw(st.integers(20, 200))
    value = draw(leaf)
    for _ in range(depth):
        value = [value] if draw(st.booleans()) else {"k": value}
    return value


hostile = st.one_of(leaf, leaf, nested, deep(), st.lists(numbers, min_size=1000, max_size=5000),
                    st.lists(unicode_text, min_size=200, max_size=400), st.just({}), st.just([]))


def paths(data, prefix=()):
    """Every key path of the nested tables (arrays of tables indexed)."""
    for key, value in data.items():
        here = (*prefix, key)
        yield here
        if isinstance(value, dict):
            yield from paths(value, here)
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            for k, item in enumerate(value):
                yield from paths(item, (*here, k))


def exists(data, path) -> bool:
    for key in path:
        try:
            data = data[key]
        except (KeyError, IndexError, TypeError):
            return False
    return True


def get_parent(data, path):
    for key in path[:-1]:
        data = data[key]
    return data


@st.composite
def mutated_specs(draw):
    """(the seed, TOML text, the unknown keys added (paths), what was done)."""
    origin = draw(st.sampled_from(sorted(SEEDS)))
    data = tomllib.loads(SEEDS[origin])
    done, unknown = [], []
    for _ in range(draw(st.integers(1, 3))):
        every = list(paths(data))
        kind = draw(st.sampled_from(["replace", "replace", "replace", "delete", "unknown key", "rename"]))
        if not every:
            break
        path = draw(st.sampled_from(every))
        parent = get_parent(data, path)
        if kind == "replace":
            parent[path[-1]] = draw(hostile)
        elif kind == "delete":
            del parent[path[-1]]
        else:
            table = parent[path[-1]] if isinstance(parent[path[-1]], dict) else parent
            where = path if table is not parent else path[:-1]
            key = draw(st.sampled_from(["mu", "unknwon", "dt ", "Name", "é", "models2", "__class__", ""]))
            if key in table:
                continue
            if kind == "rename" and table is parent:
                table[key] = table.pop(path[-1])
            else:
                table[key] = draw(leaf)
            if not in_free_form((*where, key)):
                unknown.append((*where, key))
        done.append(f"{kind} {'.'.join(map(str, path))}")
    unknown = [path for path in unknown if exists(data, path)]  # a later mutation may have removed it
    return origin, toml_document(data), unknown, "; ".join(done)


def names_a_key(body: str) -> bool:
    """A refusal's text (after the file's name) starts with a field's key path, an unknown key's path
    or TOML's own complaint (which gives the line and column)."""
    found = MESSAGE.match(body)
    return (body.startswith("not valid TOML") or bool(found and found["key"] in TOP_LEVEL)
            or bool(re.match(r"^[^\n]*?: unknown key; allowed in ", body)))


def check_load(text: str, unknown, base_dir: Path):
    try:
        with time_limit(10.0, "parse_experiment"):
            parse_experiment(text, base_dir, origin="fuzz.toml")
    except SpecError as refusal:
        message = str(refusal)
        assert message.startswith("fuzz.toml: "), message
        body = message.removeprefix("fuzz.toml: ")
        assert names_a_key(body), f"the refusal does not start with a key path: {message}"
        return message
    assert not unknown, f"the unknown key {'.'.join(map(str, unknown[0]))} was accepted"
    return None


@pytest.mark.parametrize("profile", PROFILES)
def test_mutated_specs_are_accepted_or_refused_naming_the_key(tmp_path, profile):
    @fuzz_settings(profile, scale=2)
    @given(mutated_specs())
    def check(drawn):
        origin, text, unknown, done = drawn
        note(f"{origin}: {done}\n{text[:2000]}")
        message = check_load(text, unknown, tmp_path)
        if message and unknown and ";" not in done:  # the one mutation added an unknown key: it is the one named
            assert f"{unknown[0][-1]}: unknown key" in message, message

    check()


@st.composite
def raw_specs(draw):
    """Bytes of any kind: junk, non-UTF-8 text, BOMs, a valid spec cut short or with bytes flipped."""
    seed = SEEDS[draw(st.sampled_from(sorted(SEEDS)))].encode()
    kind = draw(st.sampled_from(["junk", "cut", "flip", "latin-1", "bom", "utf-16"]))
    if kind == "junk":
        return draw(st.binary(max_size=400))
    if kind == "cut":
        return seed[: draw(st.integers(0, len(seed)))]
    if kind == "flip":
        k = draw(st.integers(0, len(seed) - 1))
        return seed[:k] + bytes([draw(st.integers(0, 255))]) + seed[k + 1:]
    if kind == "latin-1":
        return seed.replace(b"# ", "# é ".encode("latin-1"), 1)
    if kind == "bom":
        return b"\xef\xbb\xbf" + seed
    return seed.decode().encode("utf-16")


@pytest.mark.parametrize("profile", PROFILES)
def test_raw_spec_files_are_loaded_or_refused_naming_the_file(tmp_path, profile):
    @fuzz_settings(profile, scale=2)
    @given(raw_specs())
    def check(content):
        path = tmp_path / "spec.toml"
        path.write_bytes(content)
        note(repr(content[:300]))
        try:
            with time_limit(10.0, "load_experiment"):
                load_experiment(path)
        except SpecError as refusal:
            message = str(refusal)
            assert message.startswith(f"{path}: "), message
            body = message.removeprefix(f"{path}: ")
            assert body.startswith("not UTF-8") or names_a_key(body), message

    check()


def test_the_seeds_are_valid_and_the_writer_round_trips(tmp_path):
    """The mutations start from valid specs, and the writer reproduces them (else the fuzz tests the writer)."""
    for origin, text in SEEDS.items():
        data = tomllib.loads(text)
        assert tomllib.loads(toml_document(data)) == data, origin
        parse_experiment(toml_document(data), tmp_path, origin=origin)


@pytest.mark.parametrize("key, value, expected", [
    ("integration", {"alpha": math.nan}, "integration.alpha: "),
    ("integration", {"dt_integration": "inf"}, "integration.dt_integration: "),
    ("intensities", {"levels": ["D_II"] * 5000}, "intensities.levels: "),
    ("output", {"nested": {"k": {"k": {"k": 1}}}}, "output.nested: unknown key"),
    ("run", {"cell_timeout": -1.0}, "run.cell_timeout: "),
])
def test_hand_picked_hostile_values_name_their_key(tmp_path, key, value, expected):
    data = tomllib.loads(DEFAULT_TOML)
    data[key] = {**data.get(key, {}), **value}
    with pytest.raises(SpecError) as refused:
        parse_experiment(toml_document(data), tmp_path, origin="x.toml")
    assert str(refused.value).startswith(f"x.toml: {expected}"), str(refused.value)


# -- through the command line -----------------------------------------------------------------------

CLI_CASES = [
    ("unknown key", lambda d: d["integration"].update(alhpa=0.1), "integration.alhpa: unknown key"),
    ("NaN", lambda d: d["integration"].update(alpha=math.nan), "integration.alpha: "),
    ("wrong type", lambda d: d.update(records="AT2"), "records: must be tables"),
    ("no models", lambda d: d.pop("models"), "models: the experiment needs at least one"),
    ("huge list", lambda d: d["intensities"].update(levels=[1e300] * 3000), "intensities.levels: "),
]


@pytest.mark.parametrize("what, mutate, expected", CLI_CASES, ids=[c[0] for c in CLI_CASES])
def test_bearingfw_run_refuses_a_bad_spec_with_status_2_and_writes_nothing(tmp_path, what, mutate, expected):
    data = tomllib.loads(DEFAULT_TOML)
    mutate(data)
    spec = tmp_path / "spec.toml"
    spec.write_text(toml_document(data), encoding="utf-8")
    out = tmp_path / "results"
    err = io.StringIO()
    with redirect_stdout(io.StringIO()), redirect_stderr(err):  # in this process: a subprocess costs ~10 s here
        status = main(["run", str(spec), "--out", str(out)])
    lines = err.getvalue().splitlines()
    assert status == 2, err.getvalue()
    assert len(lines) == 1 and lines[0].startswith(f"bearingfw run: error: {spec}: {expected}"), err.getvalue()
    assert not out.exists() or not any(out.iterdir()), sorted(p.name for p in out.iterdir())


def test_bearingfw_run_refuses_a_spec_that_is_not_utf8(tmp_path):
    """As a user runs it (a subprocess): one line, no traceback, status 2, no output directory."""
    spec = tmp_path / "spec.toml"
    spec.write_bytes(DEFAULT_TOML.encode().replace(b"# ", "# é ".encode("latin-1"), 1))
    out = tmp_path / "results"
    done = subprocess.run([sys.executable, "-m", "bearingfw", "run", str(spec), "--out", str(out)],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 2 and "not UTF-8" in done.stderr and "Traceback" not in done.stderr, done.stderr
    assert not out.exists()
