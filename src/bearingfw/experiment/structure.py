"""The model of a cell: the structure (a builder of :mod:`bearingfw.structures`) with a bearing model.

The structure is what ``[structure] builder`` returns when called with ``options``
(:func:`bearingfw.structures.build_structure`: the built-in reference bridge, a
``package.module:function`` or a ``path/to/file.py:function``). The bearing model then goes on
the governed connectors (``[structure] bearings``, default every connector that is not JOIN):

- a ``law`` model: that law with its parameters on each of them (``Model.with_law``);
- a ``preset`` model: the laws :func:`bearingfw.bridges.preset_laws` gives each of them (a preset
  that fixes a bearing: the rigid ``fixed`` law, which ties the sliding directions; one that
  ``needs_dead_load``: each bearing's dead-load normal force with linear springs ``ks`` in
  place). A builder that takes a ``preset`` keyword applies the preset itself instead (with
  ``ks`` and ``friction`` when given), unless ``bearings`` names the connectors: a builder knows
  its bearings' layout better than "every connector that is not JOIN".

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
from collections.abc import Iterable, Sequence
from importlib import metadata
from pathlib import Path

from bearingfw.analysis import gravity
from bearingfw.bridges import DEFAULT_KS, find_preset, preset_laws
from bearingfw.experiment.spec import Experiment, ModelSpec, SpecError, StructureSpec
from bearingfw.model import ConnectorKind, FrameElement, Model, as_system
from bearingfw.parameters import ParameterError
from bearingfw.plugins import Registry, get_registry, load_registry
from bearingfw.plugins.registry import ENTRY_POINT_GROUP
from bearingfw.structures import (
    StructureError,
    build_structure,
    builder_keywords,
    import_location,
    load_builder,
    on_path,
)

__all__ = [
    "build_model",
    "mode_labeller",
    "code_inputs",
    "deck_nodes",
    "governed_bearings",
    "import_paths",
    "local_sources",
    "on_path",
    "registry_for",
    "response_elements",
    "structure_model",
]

#: How many names an error lists before "..." (a bridge has hundreds of elements).
_LISTED = 24


def _listing(names: Sequence[str]) -> str:
    names = list(names)
    shown = ", ".join(names[:_LISTED])
    return (shown + f", ... ({len(names)} in all)") if len(names) > _LISTED else (shown or "none")


def import_paths(experiment: Experiment) -> tuple[str, ...]:
    """Absolute folders for the builder and plugin modules: the experiment file's own, then ``python_path``."""
    paths = [experiment.base_dir, *(experiment.resolve_path(p) for p in experiment.python_path)]
    return tuple(dict.fromkeys(str(Path(p).resolve()) for p in paths))


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




def _builder(experiment: Experiment):
    structure = experiment.structure
    try:
        return load_builder(structure.builder, base_dir=experiment.base_dir, python_path=experiment.python_path)
    except StructureError as exc:
        raise SpecError(f"structure.builder: {exc}") from None


def mode_labeller(experiment: Experiment):
    """The function ``[structure] mode_labels`` names, or None; errors name the key."""
    spec = experiment.structure.mode_labels
    if spec is None:
        return None
    try:
        return load_builder(spec, base_dir=experiment.base_dir, python_path=experiment.python_path)
    except StructureError as exc:
        raise SpecError(f"structure.mode_labels: {exc}") from None


def structure_model(experiment: Experiment, extra: dict | None = None) -> Model:
    """What ``[structure] builder`` returns with ``options`` (and ``extra`` keywords); errors name the key."""
    structure = experiment.structure
    _builder(experiment)  # a builder that cannot be had is the builder's key's error, the rest its options'
    try:
        return build_structure(structure.builder, {**structure.options, **(extra or {})},
                               base_dir=experiment.base_dir, python_path=experiment.python_path)
    except StructureError as exc:
        key = "structure" if "calling the builder failed" in str(exc) else "structure.options"
        raise SpecError(f"{key}: {exc}") from None


def governed_bearings(structure: StructureSpec, model: Model) -> tuple[str, ...]:
    """The connectors the bearing models govern: ``[structure] bearings`` or every non-JOIN connector."""
    if structure.bearings is not None:
        names = [c.name for c in model.connectors]
        for name in structure.bearings:
            if name not in names:
                raise SpecError(f"structure.bearings: the model has no connector {name!r}; it has {_listing(names)}")
        return structure.bearings
    return tuple(c.name for c in model.connectors if c.kind is not ConnectorKind.JOIN)


def _applies_presets(experiment: Experiment, spec: ModelSpec) -> dict | None:
    """The keywords with which the builder applies the preset ``spec`` itself, or None (module docstring)."""
    if spec.preset is None or experiment.structure.bearings is not None:
        return None
    keywords = builder_keywords(_builder(experiment))
    if keywords is None or "preset" not in keywords:
        return None
    extra = {"preset": spec.preset}
    for key in ("ks", "friction"):
        value = getattr(spec, key)
        if value is not None:
            if key not in keywords:
                raise SpecError(f"models.{spec.name}.{key}: the structure's builder applies presets itself and takes "
                                f"no {key!r}")
            extra[key] = value
    return extra


def _preset_model(spec: ModelSpec, base: Model, bearings: tuple[str, ...], registry: Registry) -> Model:
    """``base`` with the laws the preset ``spec`` gives each governed bearing."""
    preset = find_preset(spec.preset, registry)
    ks = DEFAULT_KS if spec.ks is None else spec.ks
    normal = None
    if preset.needs_dead_load:  # each bearing's dead-load N with linear springs K_s in place
        springs = base.with_law("linear-spring", {"k": ks}, connectors=bearings)
        result = gravity(as_system(springs, registry))
        normal = {b: result.normal_force(b) for b in bearings}
    friction = {} if spec.friction is None else {"friction": spec.friction}
    laws = preset_laws(preset, bearings, ks=ks, normal_forces=normal, registry=registry, **friction)
    model = base
    for b, law in laws.items():
        name, params = ("fixed", {}) if law is None else law
        model = model.with_law(name, params, connectors=[b])
    return model


def build_model(experiment: Experiment, spec: ModelSpec, registry: Registry | None = None) -> Model:
    """The experiment's structure with the bearing model ``spec`` (module docstring)."""
    registry = registry or registry_for(experiment.plugins, import_paths(experiment))
    extra = _applies_presets(experiment, spec)
    if extra is not None:
        return structure_model(experiment, extra)
    base = structure_model(experiment)
    bearings = governed_bearings(experiment.structure, base)
    if spec.law is not None:
        return base.with_law(spec.law, spec.params, connectors=bearings)
    return _preset_model(spec, base, bearings, registry)


def response_elements(structure: StructureSpec, model: Model) -> tuple[str, ...]:
    """Frame elements whose stresses are metrics: ``[structure] elements`` (default none), checked."""
    names = structure.elements or ()
    recoverable = [e.name for e in model.elements if isinstance(e, FrameElement) and e.section.points]
    for name in names:
        try:
            model.element(name)
        except ParameterError:
            raise SpecError(f"structure.elements: the model has no element {name!r}; its frame elements with "
                            f"stress recovery points: {_listing(recoverable)}") from None
        if name not in recoverable:
            raise SpecError(f"structure.elements: {name!r} is not a frame element with stress recovery points; "
                            f"those are {_listing(recoverable)}")
    return tuple(names)


def deck_nodes(structure: StructureSpec, model: Model) -> tuple[str, ...]:
    """Nodes whose absolute acceleration is a metric: ``[structure] deck_nodes`` (default none), checked."""
    names = structure.deck_nodes or ()
    for name in names:
        try:
            model.node(name)
        except ParameterError:
            raise SpecError(f"structure.deck_nodes: the model has no node {name!r}; it has "
                            f"{_listing([n.name for n in model.nodes])}") from None
    return tuple(names)


def lowest_frequencies(model: Model, registry: Registry, count: int = 2) -> tuple[float, ...]:
    """The ``count`` lowest natural frequencies (Hz) of ``model``, every law at its initial tangent."""
    from bearingfw.analysis import solve_modal

    modal = solve_modal(as_system(model, registry), count)
    return tuple(float(f) for f in modal.frequencies[:count])


def resolved_setup(experiment: Experiment, registry: Registry):
    """``(intensities, rayleigh)``: the intensities with an Sa period "T1" set to the first mode's period,
    and the Rayleigh damping with ``ratio`` put at the first two natural frequencies, both of the
    structure as its builder returns it (its own bearing laws at their initial tangent; not a
    bearing model of the experiment, so that neither depends on which models are run). One modal
    analysis, only when either needs it."""
    intensities, damping = experiment.intensities, experiment.damping
    frequencies: tuple[float, ...] = ()
    if intensities.needs_first_period or damping.needs_frequencies:
        what = "intensities.period" if intensities.needs_first_period else "damping"
        try:
            frequencies = lowest_frequencies(structure_model(experiment), registry, 2)
        except SpecError:
            raise
        except Exception as exc:  # noqa: BLE001 - a structure whose modes cannot be had
            raise SpecError(f"{what}: the structure's natural frequencies cannot be computed: "
                            f"{type(exc).__name__}: {exc}") from None
        if len(frequencies) < 2 or not all(f > 0 for f in frequencies):
            raise SpecError(f"{what}: the structure has no two positive natural frequencies "
                            f"({', '.join(f'{f:.4g}' for f in frequencies)} Hz); give [damping] ratios or alpha, "
                            "beta, and an Sa period in seconds")
    period = 1.0 / frequencies[0] if intensities.needs_first_period else None
    try:
        rayleigh = damping.rayleigh(frequencies[:2] if damping.needs_frequencies else None)
    except SpecError as exc:
        raise SpecError(f"damping: {exc}") from None
    return intensities.resolve(period), rayleigh


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


@functools.cache
def package_source_digest(package: str) -> str | None:
    """SHA-256 of the source (every ``.py`` file, by relative path and content) of the importable
    top-level ``package``, wherever it is installed (an editable checkout too); None if it has no
    source files here. Cached per process: the source of a running process does not change under it."""
    try:
        spec = importlib.util.find_spec(package)
    except (ImportError, ValueError):
        return None
    if spec is None:
        return None
    if spec.submodule_search_locations:
        files = sorted((Path(root), f) for root in spec.submodule_search_locations for f in Path(root).rglob("*.py"))
    elif spec.origin and spec.origin.endswith(".py"):
        files = [(Path(spec.origin).parent, Path(spec.origin))]
    else:
        return None
    digest = hashlib.sha256()
    for root, path in files:
        try:
            data = path.read_bytes()
        except OSError:
            continue
        digest.update(path.relative_to(root).as_posix().encode() + b"\0" + hashlib.sha256(data).digest())
    return digest.hexdigest() if files else None


def _package_of(value) -> str | None:
    module = getattr(value, "__module__", None) or getattr(type(value), "__module__", None)
    return module.partition(".")[0] if isinstance(module, str) else None


def code_inputs(experiment: Experiment, registry: Registry, laws: Iterable[str], readers: Iterable[str] = ()) -> dict:
    """What code a cell's result depends on beyond its data: bearingfw's version; the version of the
    distribution of each law ``laws``, record reader ``readers``, the intensity scale it uses and the
    metric families; ``package_sources``: the digest of the source of bearingfw and of the packages
    those come from (:func:`package_source_digest`: an edit in a development checkout counts); and
    the source files (:func:`local_sources`) of the experiment's own modules:
    the structure's builder and the ``plugins`` modules that contribute one of those. Such a module
    that belongs to an installed distribution (and is not in the experiment's folders) counts by
    that version."""
    from bearingfw import __version__
    from bearingfw.motion.intensity import DEFAULT_SCALE_NAME

    paths = import_paths(experiment)
    entries = [registry.laws[name] for name in sorted(set(laws))]
    entries += [registry.record_readers[name] for name in sorted(set(readers))]
    scale = registry.intensity_scales.get(experiment.intensities.scale or DEFAULT_SCALE_NAME)
    entries += [scale] if scale is not None else []
    entries += list(registry.metrics.values())  # the metrics are part of a cell's result
    origins = [entry.origin for entry in entries]
    distributions = {o.distribution: o.version for o in origins if o.distribution}
    # The source, not only the version: a law edited in a development checkout keeps its version.
    packages = {"bearingfw"} | {_package_of(e.value) for e in entries
                                if e.origin.distribution and not e.origin.plugin.startswith("experiment:")}
    package_sources = {p: package_source_digest(p) for p in sorted(q for q in packages if q)}
    sources: dict = {}
    own = {o.plugin.partition(":")[2] for o in origins if o.plugin.startswith("experiment:")}
    builder, folders = import_location(experiment.structure.builder, base_dir=experiment.base_dir,
                                       python_path=experiment.python_path)
    if builder.partition(".")[0] != "bearingfw":  # bearingfw's own builders count by its version
        own.add(builder)
        paths = tuple(dict.fromkeys((*folders, *paths)))
    for name in sorted(own):
        if _module_file(name, paths) is not None:
            sources[name] = local_sources(name, paths)
        elif (installed := _installed_version(name)) is not None:
            distributions[installed[0]] = installed[1]
        else:  # elsewhere on sys.path: its own sources, from the folder it is imported from
            sources[name] = local_sources(name, _home(name))
    return {"bearingfw": __version__, "distributions": dict(sorted(distributions.items())),
            "package_sources": package_sources, "sources": dict(sorted(sources.items()))}
