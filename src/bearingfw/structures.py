"""Loading a structure: the paper's reference bridge or a user's own builder function.

A *structure spec* names a function that returns a :class:`bearingfw.model.Model`:

- ``"reference"`` (:data:`REFERENCE`): the paper's bridge of :mod:`bearingfw.bridges`. Its options
  are the fields of :class:`bearingfw.bridges.BridgeParameters`, plus ``preset`` (a bearing model
  of :data:`bearingfw.bridges.PRESETS`, default ``M0``), ``ks`` (stick stiffness K_s, N/m) and
  ``friction`` (the coefficient of M2 and bouc-wen);
- ``"package.module:function"``: imported with ``base_dir`` and ``python_path`` in front of
  ``sys.path``;
- ``"path/to/file.py:function"``: the file (relative to ``base_dir``, default the current folder)
  is imported as the module named by its stem, with its folder on ``sys.path`` (so it may import
  its neighbours); if another module of that name is already imported, the file is loaded under a
  private name instead. As with any import, a module is imported once per process: a later spec
  naming the same module gets that one.

The options are the function's keyword arguments (``--option key=value`` on the command line,
``[structure] options`` in an experiment file). Every failure - module or file not found, an error
while importing it, no such function, a keyword the function does not take, the builder raising
(or calling ``sys.exit``), a result that is not a Model - is a :class:`StructureError` (a
:class:`ParameterError`) whose message names the spec and what is wrong, so the commands print one
line, not a traceback. When the builder (or, with ``check``, the model's bearing laws) refuses a
value, the failure is put on the one option without which the model builds, if there is one
(:attr:`StructureError.option`), and the message starts with how the user gave it
(``origins``: ``--option k=abc``, ``--param k = 1e+07 (LOW)``).
"""

from __future__ import annotations

import contextlib
import difflib
import hashlib
import importlib
import importlib.util
import inspect
import keyword
import re
import sys
import tomllib
import traceback
from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path

import attrs

from bearingfw.model import Model
from bearingfw.parameters import ParameterError

__all__ = [
    "OPTION_HELP",
    "REFERENCE",
    "STRUCTURE_HELP",
    "StructureError",
    "build_structure",
    "builder_keywords",
    "builder_signature",
    "import_location",
    "load_builder",
    "on_path",
    "option_origins",
    "parse_options",
    "reference_ignores",
    "reference_options",
    "reference_parameters",
]

#: The spec of the paper's reference bridge.
REFERENCE = "reference"

#: The help of ``--structure`` and ``--option`` on the commands (the same words everywhere).
STRUCTURE_HELP = (
    "your structure: 'package.module:function' or 'path/to/file.py:function', a function returning a "
    "bearingfw Model (as the experiment's [structure] builder); default: the paper's reference bridge"
)
OPTION_HELP = (
    "a keyword argument of the structure's function, repeatable (as [structure] options); VALUE is read as a "
    "TOML value (4e8, true, [1, 2], \"text\"), a bare word as text"
)

_DOTTED = r"[A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)*"
_MODULE_FUNCTION = re.compile(rf"^({_DOTTED}):([A-Za-z_][A-Za-z0-9_]*)$")
_FILE_FUNCTION = re.compile(r"^(.+\.py):([A-Za-z_][A-Za-z0-9_]*)$")
_FORMS = f"{REFERENCE!r}, 'package.module:function' or 'path/to/file.py:function'"


class StructureError(ParameterError):
    """A structure spec or its options cannot give a model (the message says which and why).

    ``option``: the option the failure is put on, when one alone causes it (else None)."""

    def __init__(self, message: str, option: str | None = None):
        super().__init__(message)
        self.option = option


# --- the reference bridge ---------------------------------------------------------------------

_REFERENCE_EXTRA = ("preset", "ks", "friction")


def reference_options() -> tuple[str, ...]:
    """The options of the reference bridge: ``preset``, ``ks``, ``friction`` and BridgeParameters' fields."""
    from bearingfw.bridges import BridgeParameters

    return (*_REFERENCE_EXTRA, *(f.name for f in attrs.fields(BridgeParameters)))


def reference_parameters(options: Mapping) -> tuple[str, float, float, object]:
    """``(preset, ks, friction, BridgeParameters)`` of the reference bridge from its ``options``
    (an unknown option or a value out of range: a :class:`StructureError` naming it)."""
    from bearingfw.bridges import DEFAULT_KS, PRESETS, BridgeParameters
    from bearingfw.bridges.paper import FRICTION

    options = dict(options)
    _check_keywords(REFERENCE, options, reference_options(), takes_any=False)
    preset = options.pop("preset", "M0")
    ks = options.pop("ks", DEFAULT_KS)
    friction = options.pop("friction", FRICTION)
    if not isinstance(preset, str) or preset not in PRESETS:
        raise StructureError(f"structure {REFERENCE!r}: option 'preset' must be one of {', '.join(PRESETS)}, "
                             f"got {preset!r}")
    for name, value in (("ks", ks), ("friction", friction)):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise StructureError(f"structure {REFERENCE!r}: option {name!r} must be a number, got {value!r}")
    try:
        params = BridgeParameters(**options)
    except (ParameterError, TypeError) as exc:  # TypeError: an attrs converter refusing a value's type
        raise StructureError(f"structure {REFERENCE!r}: {exc}") from None
    return preset, float(ks), float(friction), params


def reference_ignores(options: Mapping, name: str) -> str | None:
    """The reference bridge's preset in ``options`` if its bearing law does not use ``name`` (``"ks"`` or
    ``"friction"``), else None: M0 (frictionless) has no K_s, so calibrating ``ks`` on it changes nothing.

    The preset is asked for one bearing's law at two values of ``name`` (presets come from plugins:
    their laws are the only record of what they read)."""
    from bearingfw.bridges import DEFAULT_KS
    from bearingfw.bridges.paper import FRICTION
    from bearingfw.bridges.presets import find_preset
    from bearingfw.plugins import PresetBearing

    if name not in ("ks", "friction"):
        return None
    preset = options.get("preset", "M0")
    chosen = find_preset(preset)
    dead_load = 1e6 if chosen.needs_dead_load else None  # any compressive force: only the difference matters
    laws = []
    for factor in (1.0, 0.5):
        values = {"ks": DEFAULT_KS, "friction": FRICTION}
        values[name] *= factor
        laws.append(chosen.law(PresetBearing("probe", values["ks"], values["friction"], dead_load)))
    return None if laws[0] != laws[1] else chosen.name


def _reference_bridge(**options) -> Model:
    """The paper's bridge with ``preset``/``ks``/``friction`` and BridgeParameters ``options``."""
    from bearingfw.bridges import reference_bridge

    preset, ks, friction, params = reference_parameters(options)
    try:
        return reference_bridge(preset, ks=ks, params=params, friction=friction)
    except ParameterError as exc:
        raise StructureError(f"structure {REFERENCE!r}: {exc}") from None


# --- loading a builder ----------------------------------------------------------------------------


@contextlib.contextmanager
def on_path(paths: Iterable[str]):
    """``paths`` in front of ``sys.path`` while the block runs (modules imported stay imported)."""
    added = [p for p in dict.fromkeys(paths) if p not in sys.path]
    sys.path[:0] = added
    try:
        yield
    finally:
        for p in added:
            with contextlib.suppress(ValueError):
                sys.path.remove(p)


def _parse_spec(spec) -> tuple[str, str, bool]:
    """(module or file, function, is_file) of a spec other than the reference; an error names the forms."""
    if not isinstance(spec, str) or not spec.strip():
        raise StructureError(f"structure spec must be {_FORMS}, got {spec!r}")
    spec = spec.strip()
    # a file first: "x.py:f" names the file x.py, not a submodule "py" of a package x
    if match := _FILE_FUNCTION.match(spec):
        return match.group(1), match.group(2), True
    if match := _MODULE_FUNCTION.match(spec):
        return match.group(1), match.group(2), False
    hint = ""
    if ":" not in spec:
        hint = " (the function is missing: add ':function')"
    elif spec.rpartition(":")[2] and not spec.rpartition(":")[2].isidentifier():
        hint = f" ({spec.rpartition(':')[2]!r} is not a function name)"
    raise StructureError(f"structure {spec!r}: expected {_FORMS}{hint}")


def _resolve_dir(base_dir: Path | str | None) -> Path:
    return Path.cwd() if base_dir is None else Path(base_dir)


def import_location(
    spec: str, *, base_dir: Path | str | None = None, python_path: Sequence[str | Path] = ()
) -> tuple[str, tuple[str, ...]]:
    """(module name, folders put in front of ``sys.path``) under which ``spec``'s module is imported.

    For ``path/to/file.py:function``: the file's stem and its folder first. For the reference
    bridge: ``("bearingfw.bridges", ())``. Relative ``python_path`` entries are relative to
    ``base_dir``. (What an experiment hashes to know the builder's sources.)
    """
    if spec == REFERENCE:
        return "bearingfw.bridges", ()
    target, _, is_file = _parse_spec(spec)
    root = _resolve_dir(base_dir)
    folders = [root, *(root / Path(p) for p in python_path)]
    if is_file:
        path = (root / target).resolve()
        return path.stem, tuple(dict.fromkeys(str(p) for p in (path.parent, *(f.resolve() for f in folders))))
    return target, tuple(dict.fromkeys(str(f.resolve()) for f in folders))


def _user_error(spec: str, doing: str, exc: BaseException) -> StructureError:
    """An error raised by the user's code (importing their module, calling their builder), with
    where it happened: one line instead of a traceback."""
    where = ""
    frames = traceback.extract_tb(exc.__traceback__)
    # the innermost frame outside Python's import machinery and bearingfw itself: the user's line
    ours = str(Path(__file__).resolve().parent)
    user = [f for f in frames if "importlib" not in f.filename and not f.filename.startswith(("<frozen", ours))]
    text = str(exc)
    if isinstance(exc, SyntaxError) and exc.filename:
        text = exc.msg  # str() of a SyntaxError adds "(file, line n)": the location is given once, below
        where = f" ({exc.filename}, line {exc.lineno})"
    elif user:
        where = f" ({user[-1].filename}, line {user[-1].lineno})"
    if isinstance(exc, SystemExit):
        return StructureError(f"structure {spec!r}: {doing} failed: it called sys.exit({exc.code!r}){where}")
    return StructureError(f"structure {spec!r}: {doing} failed: {type(exc).__name__}: {text}{where}")


def _import_file(spec: str, path: Path, folders: tuple[str, ...]):
    if not path.is_file():
        raise StructureError(f"structure {spec!r}: file {str(path)!r} not found")
    name = path.stem
    if name.isidentifier() and not keyword.iskeyword(name):
        # Imported under its own name, as `module:function` with its folder on the path would be
        # (worker processes re-import it the same way), unless that name is another file's.
        loaded = sys.modules.get(name)
        if loaded is None or _same_file(getattr(loaded, "__file__", None), path):
            try:
                with on_path(folders):
                    module = importlib.import_module(name)
            except (Exception, SystemExit) as exc:  # noqa: BLE001 - whatever the user's module raises
                raise _user_error(spec, f"importing file {str(path)!r}", exc) from None
            if _same_file(getattr(module, "__file__", None), path):
                return module
    # a name taken by another module (or not an identifier): a private module of its own
    unique = f"_bearingfw_structure_{hashlib.sha256(str(path).encode()).hexdigest()[:12]}"
    if unique in sys.modules:
        return sys.modules[unique]
    loader_spec = importlib.util.spec_from_file_location(unique, path)
    module = importlib.util.module_from_spec(loader_spec)
    sys.modules[unique] = module
    try:
        with on_path(folders):
            loader_spec.loader.exec_module(module)
    except (Exception, SystemExit) as exc:  # noqa: BLE001
        del sys.modules[unique]
        raise _user_error(spec, f"importing file {str(path)!r}", exc) from None
    return module


def _same_file(a, b: Path) -> bool:
    if not a:
        return False
    with contextlib.suppress(OSError):
        return Path(a).resolve() == Path(b).resolve()
    return False


def _import_module(spec: str, name: str, folders: tuple[str, ...]):
    try:
        with on_path(folders):
            return importlib.import_module(name)
    except ModuleNotFoundError as exc:
        if exc.name and (name == exc.name or name.startswith(exc.name + ".")):
            raise StructureError(
                f"structure {spec!r}: module {name!r} not found (searched the installed packages and "
                f"{', '.join(folders) or 'no extra folder'}; a file is named as 'path/to/file.py:function')"
            ) from None
        raise _user_error(spec, f"importing module {name!r}", exc) from None
    except (Exception, SystemExit) as exc:  # noqa: BLE001 - whatever the user's module raises
        raise _user_error(spec, f"importing module {name!r}", exc) from None


def load_builder(
    spec: str, *, base_dir: Path | str | None = None, python_path: Sequence[str | Path] = ()
) -> Callable[..., Model]:
    """The function ``spec`` names (module docstring); :class:`StructureError` if it cannot be had."""
    if spec == REFERENCE:
        return _reference_bridge
    target, function, is_file = _parse_spec(spec)
    module_name, folders = import_location(spec, base_dir=base_dir, python_path=python_path)
    if is_file:
        module = _import_file(spec, (_resolve_dir(base_dir) / target).resolve(), folders)
    else:
        module = _import_module(spec, module_name, folders)
    if not hasattr(module, function):
        public = sorted(n for n, v in vars(module).items()
                        if callable(v) and not n.startswith("_") and getattr(v, "__module__", None) == module.__name__)
        near = difflib.get_close_matches(function, public, n=3)
        listing = f"; did you mean {', '.join(near)}?" if near else (
            f"; its functions: {', '.join(public)}" if public else "")
        raise StructureError(f"structure {spec!r}: {target!r} has no function {function!r}{listing}")
    builder = getattr(module, function)
    if not callable(builder):
        raise StructureError(f"structure {spec!r}: {function!r} is a {type(builder).__name__}, not a function")
    return builder


def builder_signature(builder: Callable[..., Model]) -> tuple[dict[str, object], bool]:
    """``(named, takes_any)``: the keyword arguments ``builder`` names, with their defaults
    (``inspect.Parameter.empty`` if required), and whether it takes any other (``**kwargs``, or a
    signature that cannot be read)."""
    if builder is _reference_bridge:
        from bearingfw.bridges import DEFAULT_KS, BridgeParameters
        from bearingfw.bridges.paper import FRICTION

        fields = {f.name: f.default for f in attrs.fields(BridgeParameters)}
        return {"preset": "M0", "ks": DEFAULT_KS, "friction": FRICTION, **fields}, False
    try:
        signature = inspect.signature(builder)
    except (TypeError, ValueError):
        return {}, True
    named, takes_any = {}, False
    for p in signature.parameters.values():
        if p.kind is inspect.Parameter.VAR_KEYWORD:
            takes_any = True
        elif p.kind in (inspect.Parameter.POSITIONAL_OR_KEYWORD, inspect.Parameter.KEYWORD_ONLY):
            named[p.name] = p.default
    return named, takes_any


def builder_keywords(builder: Callable[..., Model]) -> dict[str, object] | None:
    """The keyword arguments ``builder`` takes, with their defaults (``inspect.Parameter.empty`` if
    required); None if it takes any keyword (``**kwargs``) other than the reference bridge's."""
    named, takes_any = builder_signature(builder)
    return None if takes_any else named


def _check_keywords(spec: str, options: Mapping, accepted: Iterable[str], takes_any: bool) -> None:
    if takes_any:
        return
    accepted = list(accepted)
    for key in options:
        if key not in accepted:
            near = difflib.get_close_matches(key, accepted, n=3)
            raise StructureError(
                f"structure {spec!r}: unknown option {key!r}"
                + (f" (did you mean {', '.join(near)}?)" if near else "")
                + f"; it takes {', '.join(accepted) if accepted else 'no options'}"
            )


# --- options -----------------------------------------------------------------------------------


def option_origins(pairs: Iterable[str] | None) -> dict[str, str]:
    """``{key: "--option key=value"}`` of the command line's ``--option`` pairs (as the user wrote them),
    the ``origins`` of :func:`build_structure`."""
    return {pair.partition("=")[0].strip(): f"--option {pair.strip()}" for pair in pairs or () if isinstance(pair, str)}


def parse_options(pairs: Iterable[str] | None) -> dict:
    """``["key=value", ...]`` as a dict; a value is read as a TOML value (``4e8``, ``true``,
    ``[1, 2]``, ``"text"``, ``{a = 1}``), a bare word as a string. Repeated keys are an error."""
    out: dict = {}
    for pair in pairs or ():
        if not isinstance(pair, str) or "=" not in pair:
            raise StructureError(f"--option {pair!r}: expected key=value")
        key, _, text = pair.partition("=")
        key, text = key.strip(), text.strip()
        if not key.isidentifier():
            raise StructureError(f"--option {pair!r}: {key!r} is not a keyword name")
        if key in out:
            raise StructureError(f"--option {pair!r}: {key!r} is given twice")
        if not text:
            raise StructureError(f"--option {pair!r}: the value is missing (write {key}=VALUE)")
        try:
            value = tomllib.loads(f"value = {text}")["value"]
        except tomllib.TOMLDecodeError as exc:
            try:
                value = float(text)  # ".5", "1.", "1E9": numbers TOML spells otherwise
            except ValueError:
                if text[0] in "[{\"'":
                    raise StructureError(f"--option {pair!r}: not a valid value ({exc})") from None
                value = text  # a bare word: a string
        out[key] = value
    return out


# --- building --------------------------------------------------------------------------------------


def build_structure(
    spec: str,
    options: Mapping | None = None,
    *,
    base_dir: Path | str | None = None,
    python_path: Sequence[str | Path] = (),
    check: bool = False,
    origins: Mapping[str, str] | None = None,
) -> Model:
    """The model ``spec``'s builder returns when called with ``options`` as keyword arguments.

    ``check``: also assemble the model (:func:`bearingfw.model.build_system`), where the bearing
    laws check their parameters, so that a value the model refuses fails here. A failure of the
    builder or of that check is put on the one option without which the model builds, if there is
    one (module docstring); ``origins[key]`` says how the user gave that option (default
    ``option key = value``).
    """
    options = dict(options or {})
    builder = load_builder(spec, base_dir=base_dir, python_path=python_path)
    accepted = builder_keywords(builder)
    if accepted is not None:
        _check_keywords(spec, options, accepted, takes_any=False)
        missing = [k for k, v in accepted.items() if v is inspect.Parameter.empty and k not in options]
        if missing:
            raise StructureError(f"structure {spec!r}: option(s) {', '.join(map(repr, missing))} required")
    try:
        return _call_builder(spec, builder, options, check)
    except StructureError as exc:
        culprit = _culprit(spec, builder, options, check, accepted)
        if culprit is None:
            raise
        origin = (origins or {}).get(culprit) or f"option {culprit} = {options[culprit]!r}"
        raise StructureError(f"{origin}: {exc}", option=culprit) from None


def _call_builder(spec: str, builder: Callable[..., Model], options: Mapping, check: bool) -> Model:
    try:
        model = builder(**options)
    except StructureError:
        raise
    except ParameterError as exc:
        raise StructureError(f"structure {spec!r}: {exc}") from None
    except (Exception, SystemExit) as exc:  # noqa: BLE001 - the user's builder failing, whatever the error
        raise _user_error(spec, "calling the builder", exc) from None
    if not isinstance(model, Model):
        raise StructureError(f"structure {spec!r}: the builder returned {type(model).__name__}, not a bearingfw Model")
    if check:
        from bearingfw.model import build_system

        try:
            build_system(model)
        except ParameterError as exc:
            raise StructureError(f"structure {spec!r}: {exc}") from None
    return model


def _culprit(spec: str, builder, options: Mapping, check: bool, accepted: Mapping | None) -> str | None:
    """The one option without which (at the builder's default) the model builds, or None.

    Only asked when building failed, so its cost (one build per option) is paid on that path."""
    keys = [k for k in options if accepted is None or accepted.get(k, inspect.Parameter.empty)
            is not inspect.Parameter.empty]
    found = []
    for key in keys:
        try:
            _call_builder(spec, builder, {k: v for k, v in options.items() if k != key}, check)
        except StructureError:
            continue
        found.append(key)
    return found[0] if len(found) == 1 else None
