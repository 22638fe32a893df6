"""Plugin discovery and the registries built from the hooks.

``load_registry()`` finds every plugin in the entry-point group ``bearingfw`` (the built-in
ones included), registers it with pluggy, and asks each plugin, one at a time, for its
contributions. Anything that goes wrong (an import error, a hook that raises, a contribution
that fails its check, a name taken twice) becomes a :class:`BrokenPlugin` entry and the other
plugins load as usual.

Adding a hook takes a hookspec in ``hookspecs.py`` and one ``_collect`` call in
``load_registry`` with a function that checks a contribution and returns its key.
"""

from __future__ import annotations

import importlib.metadata as metadata
import inspect
import traceback
from collections.abc import Callable, Iterable
from typing import Any

import attrs
import pluggy

from bearingfw.parameters import ParameterError
from bearingfw.plugins import hookspecs
from bearingfw.plugins.contracts import BearingPreset, IntensityScale
from bearingfw.protocol import PROTOCOL_MEMBERS, BearingLaw

ENTRY_POINT_GROUP = "bearingfw"


class UnknownLawError(KeyError):
    """No installed plugin registers a law of that name."""

    def __str__(self) -> str:  # KeyError would show the message in quotes
        return str(self.args[0])


@attrs.frozen
class Origin:
    """Where a contribution came from."""

    plugin: str
    distribution: str | None
    version: str | None


@attrs.frozen
class Entry:
    """One contribution of one plugin, under its registry key."""

    key: str
    value: Any
    origin: Origin


@attrs.frozen
class BrokenPlugin:
    plugin: str
    error: str
    distribution: str | None = None


@attrs.frozen
class Registry:
    """What the loaded plugins contribute: ``laws`` maps a law name to its entry.

    ``record_readers`` and ``intensity_scales`` map a reader's or a scale's name to its entry.
    """

    laws: dict[str, Entry]
    broken: tuple[BrokenPlugin, ...]
    plugin_manager: pluggy.PluginManager = attrs.field(repr=False, eq=False)
    record_readers: dict[str, Entry] = attrs.field(factory=dict)
    intensity_scales: dict[str, Entry] = attrs.field(factory=dict)
    presets: dict[str, Entry] = attrs.field(factory=dict)
    metrics: dict[str, Entry] = attrs.field(factory=dict)
    executors: dict[str, Entry] = attrs.field(factory=dict)

    def preset(self, name: str) -> BearingPreset:
        """The preset called ``name``; :class:`UnknownPresetError` names the known ones."""
        try:
            return self.presets[name].value
        except KeyError:
            known = ", ".join(sorted(self.presets)) or "(none)"
            raise UnknownPresetError(f"unknown bearing preset {name!r}; known presets: {known}") from None

    def law_class(self, name: str) -> type:
        try:
            return self.laws[name].value
        except KeyError:
            known = ", ".join(sorted(self.laws)) or "(none: is bearingfw installed with pip?)"
            raise UnknownLawError(f"unknown bearing law {name!r}; known laws: {known}") from None


class UnknownPresetError(KeyError):
    """No installed plugin registers a preset of this name."""

    def __str__(self) -> str:
        return str(self.args[0]) if self.args else ""


def _preset_key(preset: Any) -> str:
    if not isinstance(preset, BearingPreset):
        raise TypeError(
            f"bearingfw_register_presets must return bearingfw.BearingPreset objects, got {preset!r}"
        )
    return preset.name


def _named_key(kind: str) -> Callable[[Any], str]:
    """The check of a duck-typed contribution that the registry only knows by its ``name``."""

    def key(item: Any) -> str:
        name = getattr(item, "name", None)
        if not isinstance(name, str) or not name:
            raise TypeError(f"{kind} {item!r}: 'name' must be a non-empty string")
        return name

    return key


def _law_key(cls: Any) -> str:
    """Check a contributed law class against the protocol and return its name."""
    if not inspect.isclass(cls):
        raise TypeError(f"bearingfw_register_laws must return classes, got {cls!r}")
    params = _constructor_parameter_names(cls)
    missing = [m for m in PROTOCOL_MEMBERS if not hasattr(cls, m) and m not in params]
    if missing:
        raise TypeError(f"law class {cls.__qualname__} lacks protocol member(s) {', '.join(missing)}")
    name = getattr(cls, "name", None)
    if not isinstance(name, str) or not name:
        raise TypeError(f"law class {cls.__qualname__}: 'name' must be a non-empty class attribute string")
    for method in ("initial_state", "respond"):
        if not callable(getattr(cls, method)):
            raise TypeError(f"law class {cls.__qualname__}: {method!r} must be a method")
    return name


def _reader_key(reader: Any) -> str:
    """Check a contributed record reader (duck-typed, see the hookspec) and return its name."""
    name = getattr(reader, "name", None)
    if not isinstance(name, str) or not name:
        raise TypeError(f"record reader {reader!r}: 'name' must be a non-empty string")
    from bearingfw.plugins.contracts import check_suffixes  # the one suffix check, shared with RecordReader

    check_suffixes(name, getattr(reader, "suffixes", None))
    if not callable(getattr(reader, "read", None)):
        raise TypeError(f"record reader {name!r}: 'read' must be callable")
    sniff = getattr(reader, "sniff", None)
    if sniff is not None and not callable(sniff):
        raise TypeError(f"record reader {name!r}: 'sniff' must be callable or None")
    return name


def _scale_key(scale: Any) -> str:
    """Check a contributed intensity scale (validated data, see the hookspec) and return its name."""
    if not isinstance(scale, IntensityScale):
        raise TypeError(
            f"bearingfw_register_intensity_scales must return bearingfw.motion.IntensityScale objects, got {scale!r}"
        )
    return scale.name


def _constructor_parameter_names(cls: type) -> list[str]:
    try:
        signature = inspect.signature(cls)
    except (TypeError, ValueError):
        return []
    return [p.name for p in signature.parameters.values() if p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)]


def _origin(plugin_name: str, dist: metadata.Distribution | None) -> Origin:
    if dist is None:
        return Origin(plugin_name, None, None)
    return Origin(plugin_name, dist.metadata["Name"], dist.version)


def _short_error(exc: BaseException) -> str:
    return "".join(traceback.format_exception_only(type(exc), exc)).strip()


def _collect(
    pm: pluggy.PluginManager,
    hook_name: str,
    key_of: Callable[[Any], str],
    origins: dict[str, Origin],
    broken: list[BrokenPlugin],
    preferred_distribution: str = "bearingfw",
) -> dict[str, Entry]:
    """Call one hook plugin by plugin; check each contribution; resolve duplicate keys.

    When two plugins claim one key, bearingfw's own plugin keeps it; otherwise the first plugin
    (by plugin name) keeps it, and the other is reported broken.
    """
    caller = getattr(pm.hook, hook_name)
    impls = sorted(
        caller.get_hookimpls(),
        key=lambda impl: (origins[impl.plugin_name].distribution != preferred_distribution, impl.plugin_name),
    )
    entries: dict[str, Entry] = {}
    for impl in impls:
        origin = origins[impl.plugin_name]
        try:
            contributions = list(impl.function() or [])
        except Exception as exc:  # a third-party hook may raise anything
            broken.append(BrokenPlugin(impl.plugin_name, f"{hook_name} raised {_short_error(exc)}", origin.distribution))
            continue
        for item in contributions:
            try:
                key = key_of(item)
            except Exception as exc:
                broken.append(BrokenPlugin(impl.plugin_name, _short_error(exc), origin.distribution))
                continue
            if key in entries:
                first = entries[key].origin.plugin
                broken.append(
                    BrokenPlugin(
                        impl.plugin_name,
                        f"{hook_name}: name {key!r} is already registered by plugin {first!r}; this one is ignored",
                        origin.distribution,
                    )
                )
                continue
            entries[key] = Entry(key, item, origin)
    return entries


def load_registry(entry_points: Iterable[metadata.EntryPoint] | None = None) -> Registry:
    """Discover plugins and build the registry.

    ``entry_points`` defaults to the installed entry points of the group ``bearingfw``; tests
    pass their own.
    """
    if entry_points is None:
        entry_points = metadata.entry_points(group=ENTRY_POINT_GROUP)
    pm = pluggy.PluginManager(ENTRY_POINT_GROUP)
    pm.add_hookspecs(hookspecs)
    origins: dict[str, Origin] = {}
    broken: list[BrokenPlugin] = []
    for ep in sorted(entry_points, key=lambda e: e.name):
        dist = getattr(ep, "dist", None)
        origin = _origin(ep.name, dist)
        if ep.name in origins:
            broken.append(BrokenPlugin(ep.name, "another plugin of this name is already loaded", origin.distribution))
            continue
        try:
            plugin = ep.load()
            pm.register(plugin, name=ep.name)
        except Exception as exc:  # import errors, bad hookimpls (pluggy validation), anything
            broken.append(BrokenPlugin(ep.name, f"could not load {ep.value!r}: {_short_error(exc)}", origin.distribution))
            continue
        origins[ep.name] = origin
    broken.extend(_unknown_hooks(pm, origins))
    laws = _collect(pm, "bearingfw_register_laws", _law_key, origins, broken)
    readers = _collect(pm, "bearingfw_register_record_readers", _reader_key, origins, broken)
    scales = _collect(pm, "bearingfw_register_intensity_scales", _scale_key, origins, broken)
    presets = _collect(pm, "bearingfw_register_presets", _preset_key, origins, broken)
    metrics = _collect(pm, "bearingfw_register_metrics", _named_key("metric"), origins, broken)
    executors = _collect(pm, "bearingfw_register_executors", _named_key("executor"), origins, broken)
    return Registry(
        laws=laws, broken=tuple(broken), plugin_manager=pm, record_readers=readers, intensity_scales=scales,
        presets=presets, metrics=metrics, executors=executors,
    )


def _unknown_hooks(pm: pluggy.PluginManager, origins: dict[str, Origin]) -> list[BrokenPlugin]:
    """A hook implementation whose name matches no hookspec is a typo that would fail silently."""
    problems = []
    for name, caller in vars(pm.hook).items():
        if isinstance(caller, pluggy.HookCaller) and not caller.has_spec():
            for impl in caller.get_hookimpls():
                origin = origins[impl.plugin_name]
                problems.append(
                    BrokenPlugin(impl.plugin_name, f"implements unknown hook {name!r} (ignored)", origin.distribution)
                )
    return problems


_registry: Registry | None = None


def get_registry(reload: bool = False) -> Registry:
    """The process-wide registry, loaded on first use."""
    global _registry
    if _registry is None or reload:
        _registry = load_registry()
    return _registry


def describe_parameters(cls: type) -> list[dict[str, Any]]:
    """The parameters of a law class: name, required, default, allowed range, unit, doc, and
    ``per_bearing`` (the field takes one value per connector too, see :mod:`bearingfw.protocol`).

    attrs fields made with :func:`bearingfw.parameter` carry range, unit and doc; for any other
    class the constructor signature gives names and defaults.
    """
    described = []
    fields = {f.name: f for f in attrs.fields(cls)} if attrs.has(cls) else {}
    try:
        signature = inspect.signature(cls)
    except (TypeError, ValueError):
        return described
    for p in signature.parameters.values():
        if p.kind not in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY):
            continue
        meta = fields[p.name].metadata if p.name in fields else {}
        required = p.default is inspect.Parameter.empty
        described.append(
            {
                "name": p.name,
                "required": required,
                "default": None if required else p.default,
                "range": meta.get("range", "").format(name=p.name),
                "unit": meta.get("unit", ""),
                "doc": meta.get("doc", ""),
                "per_bearing": bool(meta.get("per_bearing", False)),
            }
        )
    return described


def create_law(name: str, /, *, registry: Registry | None = None, **params: Any) -> BearingLaw:
    """Build the law registered as ``name`` with ``params``.

    Raises :class:`UnknownLawError` (a ``KeyError``) listing the known names for an unknown law, and :class:`ParameterError`
    naming the parameter (and its allowed range where the law declares one) for a missing,
    unknown or invalid parameter.
    """
    registry = registry or get_registry()
    cls = registry.law_class(name)
    described = {d["name"]: d for d in describe_parameters(cls)}
    if described:
        unknown = sorted(set(params) - set(described))
        if unknown:
            raise ParameterError(
                f"{name}: unknown parameter(s) {', '.join(map(repr, unknown))}; "
                f"parameters of {name}: {', '.join(described) or 'none'}"
            )
        missing = [d for d in described.values() if d["required"] and d["name"] not in params]
        if missing:
            raise ParameterError(
                f"{name}: missing parameter(s) "
                + ", ".join(f"{d['name']!r}" + (f" ({d['range']})" if d["range"] else "") for d in missing)
            )
    try:
        law = cls(**params)
    except ParameterError:
        raise
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"{name}: {exc}") from exc
    missing_members = [m for m in PROTOCOL_MEMBERS if not hasattr(law, m)]
    if missing_members:
        raise TypeError(f"law {name!r} built an object without protocol member(s) {', '.join(missing_members)}")
    if law.dims not in (1, 2) or not isinstance(law.rigid, bool):
        raise TypeError(f"law {name!r}: dims must be 1 or 2 and rigid a bool, got dims={law.dims!r}, rigid={law.rigid!r}")
    return law
