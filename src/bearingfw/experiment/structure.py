"""The model of a cell: the structure (the reference bridge or a user's builder) with a bearing model.

Reference bridge (``[structure] builder = "reference"``): a preset model is exactly
:func:`bearingfw.bridges.reference_bridge` (the same model as ``bearingfw modal --model``); a
``law`` model puts that law on every sliding bearing (``Model.with_law``).

User builder (``"package.module:function"``): the function returns a
:class:`~bearingfw.model.Model`; the bearing model then replaces the law of the governed
connectors (``[structure] bearings``, default every connector that is not JOIN). A preset maps
to the law :data:`bearingfw.bridges.PRESETS` gives it (``fixed``: the rigid ``fixed`` law, which
ties the sliding directions; ``bouc-wen``: ``uy`` from each bearing's dead-load normal force with
linear springs ``ks`` in place, as on the reference bridge).

Plugins named by the experiment (``plugins = [...]``) are loaded besides the installed ones into
a registry of their own (:func:`registry_for`), which the cell's analyses use.
"""

from __future__ import annotations

import ast
import contextlib
import functools
import hashlib
import importlib
import importlib.util
import sys
from collections.abc import Iterable, Mapping, Sequence
from importlib import metadata
from pathlib import Path

from bearingfw.analysis import gravity
from bearingfw.bridges import (
    DEFAULT_KS,
    PRESETS,
    RESPONSE_ELEMENTS,
    BridgeParameters,
    grid,
    reference_bridge,
)
from bearingfw.bridges.paper import FRICTION
from bearingfw.experiment.spec import Experiment, ModelSpec, SpecError, StructureSpec
from bearingfw.model import ConnectorKind, FrameElement, Model, as_system
from bearingfw.parameters import ParameterError
from bearingfw.plugins import Registry, get_registry, load_registry
from bearingfw.plugins.registry import ENTRY_POINT_GROUP

__all__ = [
    "bridge_parameters",
    "build_model",
    "code_inputs",
    "deck_nodes",
    "governed_bearings",
    "import_paths",
    "local_sources",
    "on_path",
    "registry_for",
    "response_elements",
]


def import_paths(experiment: Experiment) -> tuple[str, ...]:
    """Absolute folders for the builder and plugin modules: the experiment file's own, then ``python_path``."""
    paths = [experiment.base_dir, *(experiment.resolve_path(p) for p in experiment.python_path)]
    return tuple(dict.fromkeys(str(Path(p).resolve()) for p in paths))


@contextlib.contextmanager
def on_path(paths: Iterable[str]):
    """``paths`` in front of ``sys.path`` while the block runs (modules imported stay imported)."""
    added = [p for p in paths if p not in sys.path]
    sys.path[:0] = added
    try:
        yield
    finally:
        for p in added:
            with contextlib.suppress(ValueError):
                sys.path.remove(p)


@functools.lru_cache(maxsize=8)
def registry_for(plugins: tuple[str, ...] = (), paths: tuple[str, ...] = ()) -> Registry:
    """The installed plugins' registry, plus the hook modules ``plugins`` (importable from ``paths``).

    A plugin module that fails to load is an error here (not a quiet broken-plugin entry): the
    experiment asked for it.
    """
    if not plugins:
        return get_registry()
    entry_points = list(metadata.entry_points(group=ENTRY_POINT_GROUP))
    entry_points += [metadata.EntryPoint(name=f"experiment:{m}", value=m, group=ENTRY_POINT_GROUP) for m in plugins]
    with on_path(paths):
        registry = load_registry(entry_points)
    for broken in registry.broken:
        if broken.plugin.startswith("experiment:"):
            raise SpecError(f"plugins: module {broken.plugin.split(':', 1)[1]!r}: {broken.error}")
    return registry


def _builder(structure: StructureSpec, paths: tuple[str, ...]):
    module_name, _, function = structure.builder.partition(":")
    try:
        with on_path(paths):
            module = importlib.import_module(module_name)
    except Exception as exc:  # noqa: BLE001 - an error in the user's module, whatever it is
        raise SpecError(
            f"structure.builder: cannot import module {module_name!r}: {type(exc).__name__}: {exc}"
        ) from None
    fn = getattr(module, function, None)
    if not callable(fn):
        raise SpecError(f"structure.builder: module {module_name!r} has no function {function!r}")
    return fn


def _user_structure(structure: StructureSpec, paths: tuple[str, ...]) -> Model:
    fn = _builder(structure, paths)
    try:
        model = fn(**structure.options)
    except TypeError as exc:
        raise SpecError(f"structure.options: {structure.builder} does not take them: {exc}") from None
    if not isinstance(model, Model):
        raise SpecError(
            f"structure.builder: {structure.builder} returned {type(model).__name__}, not a bearingfw Model"
        )
    return model


def bridge_parameters(structure: StructureSpec) -> BridgeParameters:
    """The reference bridge's :class:`BridgeParameters` from ``[structure] options`` (errors with the key path)."""
    from bearingfw.experiment.spec import from_table  # the loader's own key-path checks

    return from_table(BridgeParameters, structure.options, "structure.options")


def governed_bearings(structure: StructureSpec, model: Model) -> tuple[str, ...]:
    """The connectors the bearing models govern: ``[structure] bearings`` or every non-JOIN connector."""
    if structure.bearings is not None:
        for name in structure.bearings:
            try:
                model.connector(name)
            except ParameterError:
                raise SpecError(f"structure.bearings: the model has no connector {name!r}") from None
        return structure.bearings
    return tuple(c.name for c in model.connectors if c.kind is not ConnectorKind.JOIN)


def _preset_laws(spec: ModelSpec, base: Model, bearings: tuple[str, ...], registry: Registry) -> dict:
    """The (law, params) of each governed bearing under a preset, on a user's structure."""
    preset = PRESETS[spec.preset]
    ks = DEFAULT_KS if spec.ks is None else spec.ks
    mu = FRICTION if spec.friction is None else spec.friction
    normal: Mapping[str, float] = {}
    if preset.needs_dead_load:  # as on the reference bridge: N at dead load with linear springs K_s in place
        springs = base.with_law("linear-spring", {"k": ks}, connectors=bearings)
        result = gravity(as_system(springs, registry))
        normal = {b: result.normal_force(b) for b in bearings}
    laws = {}
    for b in bearings:
        law = preset.law(ks, mu, normal.get(b, 0.0), BridgeParameters())
        laws[b] = ("fixed", {}) if law is None else law
    return laws


def build_model(
    structure: StructureSpec, spec: ModelSpec, registry: Registry | None = None, paths: tuple[str, ...] = ()
) -> Model:
    """The structure with the bearing model ``spec`` (module docstring)."""
    registry = registry or get_registry()
    if structure.is_reference:
        params = bridge_parameters(structure)
        if spec.preset is not None:
            ks = DEFAULT_KS if spec.ks is None else spec.ks
            mu = FRICTION if spec.friction is None else spec.friction
            return reference_bridge(spec.preset, ks=ks, params=params, friction=mu)
        return reference_bridge("M0", params=params).with_law(spec.law, spec.params)
    base = _user_structure(structure, paths)
    bearings = governed_bearings(structure, base)
    if spec.preset is None:
        return base.with_law(spec.law, spec.params, connectors=bearings)
    model = base
    for b, (law, params) in _preset_laws(spec, base, bearings, registry).items():
        model = model.with_law(law, params, connectors=[b])
    return model


def response_elements(structure: StructureSpec, model: Model) -> tuple[str, ...]:
    """Frame elements whose stresses are metrics (reference default: the paper's :data:`RESPONSE_ELEMENTS`)."""
    names = structure.elements
    if names is None:
        names = RESPONSE_ELEMENTS if structure.is_reference else ()
    for name in names:
        try:
            element = model.element(name)
        except ParameterError:
            raise SpecError(f"structure.elements: the model has no element {name!r}") from None
        if not isinstance(element, FrameElement) or not element.section.points:
            raise SpecError(f"structure.elements: {name!r} is not a frame element with stress recovery points")
    return tuple(names)


def deck_nodes(structure: StructureSpec, model: Model) -> tuple[str, ...]:
    """Nodes whose absolute acceleration is a metric (reference default: both girders at every mid-span)."""
    names = structure.deck_nodes
    if names is None:
        if not structure.is_reference:
            return ()
        g = grid(bridge_parameters(structure))
        middles = [(a + b) // 2 for a, b in zip(g.axes, g.axes[1:])]
        names = tuple(f"G{side}{k}" for k in middles for side in "AB")
    for name in names:
        try:
            model.node(name)
        except ParameterError:
            raise SpecError(f"structure.deck_nodes: the model has no node {name!r}") from None
    return tuple(names)


def _module_file(name: str, roots: Sequence[str]) -> Path | None:
    """The source file of module ``name`` under one of ``roots`` (searched in order, a package before a
    module of the same name, as Python's import does), or None."""
    parts = name.split(".")
    for root in roots:
        base = Path(root).joinpath(*parts)
        for candidate in (base / "__init__.py", base.with_name(f"{parts[-1]}.py")):
            if candidate.is_file():
                return candidate
    return None


def _with_parents(names: Iterable[str]) -> set[str]:
    """The names and their parent packages (importing ``a.b.c`` runs ``a`` and ``a.b`` first)."""
    out = set()
    for name in names:
        parts = name.split(".")
        out.update(".".join(parts[:k]) for k in range(1, len(parts) + 1))
    return out


def _imported(tree: ast.AST, name: str, is_package: bool) -> set[str]:
    """Every module an ``import`` statement of the module ``name`` may load, anywhere in its source
    (functions included); ``from m import x`` counts ``m`` and ``m.x`` (x may be a submodule)."""
    package = name if is_package else name.rpartition(".")[0]
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            module = node.module or ""
            if node.level:
                parts = package.split(".") if package else []
                if node.level - 1 > len(parts):
                    continue  # beyond the top-level package: Python refuses it too
                module = ".".join(p for p in (*parts[:len(parts) - node.level + 1], module) if p)
            if module:
                found.add(module)
            found.update(".".join(p for p in (module, alias.name) if p) for alias in node.names if alias.name != "*")
    return _with_parents(found)


def local_sources(module: str, roots: Sequence[str]) -> dict[str, str] | None:
    """SHA-256 of the source of ``module`` and of every module it imports, directly or through others,
    that lives under ``roots`` (the experiment's own folders), by module name; None if ``module`` is
    not under ``roots``.

    The imports are read from the source (``ast``), not from a run, so the result does not depend on
    what the process imported before; imports by computed name (``importlib.import_module(x)``) are
    not seen. Modules from anywhere else (bearingfw, numpy, an installed package) are identified by
    their distribution's version instead (:func:`code_inputs`).
    """
    digests: dict[str, str] = {}
    queue = sorted(_with_parents([module]))
    while queue:
        name = queue.pop()
        if name in digests:
            continue
        path = _module_file(name, roots)
        if path is None:
            continue
        data = path.read_bytes()
        digests[name] = hashlib.sha256(data).hexdigest()
        try:
            tree = ast.parse(data, filename=str(path))
        except (SyntaxError, ValueError):  # importing it fails anyway; its bytes are hashed
            continue
        queue.extend(sorted(_imported(tree, name, path.name == "__init__.py") - digests.keys()))
    return dict(sorted(digests.items())) if module in digests else None


@functools.lru_cache(maxsize=32)  # packages_distributions() reads every installed distribution's file list
def _installed_version(module: str) -> tuple[str, str] | None:
    """(distribution, version) of the installed distribution providing the top-level package of ``module``."""
    top = module.partition(".")[0]
    for distribution in metadata.packages_distributions().get(top, ()):
        with contextlib.suppress(metadata.PackageNotFoundError):
            return distribution, metadata.version(distribution)
    return None


def _home(module: str) -> tuple[str, ...]:
    """The sys.path folder the top-level package of ``module`` is imported from (none if not found)."""
    top = module.partition(".")[0]
    try:
        found = importlib.util.find_spec(top)
    except (ImportError, ValueError):
        return ()
    if found is None or not found.origin or not Path(found.origin).is_file():
        return ()
    origin = Path(found.origin)
    return (str(origin.parent.parent if found.submodule_search_locations else origin.parent),)


def code_inputs(experiment: Experiment, registry: Registry, laws: Iterable[str], readers: Iterable[str] = ()) -> dict:
    """What code a cell's result depends on beyond its data: bearingfw's version; the version of the
    distribution of each law ``laws``, record reader ``readers`` and the intensity scale it uses; and
    the source files (:func:`local_sources`) of the experiment's own modules: the structure's builder
    and the ``plugins`` modules that contribute one of those. Such a module that belongs to an
    installed distribution (and is not in the experiment's folders) counts by that version."""
    from bearingfw import __version__
    from bearingfw.motion.intensity import DEFAULT_SCALE_NAME

    paths = import_paths(experiment)
    origins = [registry.laws[name].origin for name in sorted(set(laws))]
    origins += [registry.record_readers[name].origin for name in sorted(set(readers))]
    scale = registry.intensity_scales.get(experiment.intensities.scale or DEFAULT_SCALE_NAME)
    origins += [scale.origin] if scale is not None else []
    distributions = {o.distribution: o.version for o in origins if o.distribution}
    sources: dict = {}
    own = {o.plugin.partition(":")[2] for o in origins if o.plugin.startswith("experiment:")}
    if not experiment.structure.is_reference:
        own.add(experiment.structure.builder.partition(":")[0])
    for name in sorted(own):
        if _module_file(name, paths) is not None:
            sources[name] = local_sources(name, paths)
        elif (installed := _installed_version(name)) is not None:
            distributions[installed[0]] = installed[1]
        else:  # elsewhere on sys.path: its own sources, from the folder it is imported from
            sources[name] = local_sources(name, _home(name))
    return {"bearingfw": __version__, "distributions": dict(sorted(distributions.items())),
            "sources": dict(sorted(sources.items()))}
