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

import contextlib
import functools
import hashlib
import importlib
import importlib.util
import sys
from collections.abc import Iterable, Mapping
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
    "deck_nodes",
    "governed_bearings",
    "import_paths",
    "module_digest",
    "on_path",
    "registry_for",
    "response_elements",
    "source_versions",
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


def module_digest(module_name: str, paths: tuple[str, ...]) -> str | None:
    """SHA-256 of a module's source file (None if it has none), found with ``paths`` on sys.path."""
    with on_path(paths):
        try:
            found = importlib.util.find_spec(module_name)
        except (ImportError, ValueError):
            return None
    origin = getattr(found, "origin", None)
    if not origin or not Path(origin).is_file():
        return None
    return hashlib.sha256(Path(origin).read_bytes()).hexdigest()


def source_versions(experiment: Experiment, registry: Registry) -> dict:
    """What code a cell's result depends on beyond its inputs: bearingfw's and the plugin
    distributions' versions, and the source of the experiment's own modules (builder, plugins)."""
    from bearingfw import __version__

    paths = import_paths(experiment)
    distributions = {}
    for table in (registry.laws, registry.record_readers, registry.intensity_scales):
        for entry in table.values():
            if entry.origin.distribution:
                distributions[entry.origin.distribution] = entry.origin.version
    modules = {m: module_digest(m, paths) for m in experiment.plugins}
    if not experiment.structure.is_reference:
        name = experiment.structure.builder.partition(":")[0]
        modules[name] = module_digest(name, paths)
    return {"bearingfw": __version__, "distributions": dict(sorted(distributions.items())), "modules": modules}
