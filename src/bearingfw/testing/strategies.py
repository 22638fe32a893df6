"""Hypothesis strategies for bearing laws: displacement paths, normal forces, velocities, parameters."""

from __future__ import annotations

import attrs
import numpy as np
from hypothesis import assume
from hypothesis import strategies as st

from bearingfw.parameters import ParameterError


# Arrays are drawn as one block of bytes and mapped to numbers: hypothesis draws (and shrinks)
# one binary string several times faster than a list of floats, which made data generation the
# bulk of a conformance run. Each number takes three bytes: a control byte and a 16-bit value.
# Zero bytes map to zero, so shrinking leads to paths that stand still.
_ZERO_BELOW, _EDGE_BELOW = 32, 48  # control bytes: 1/8 exact zeros, 1/16 exact edges (+-1)


@st.composite
def unit_arrays(draw, shape: tuple[int, ...]):
    """Numbers in ``[-1, 1]`` of ``shape``: 1/8 exactly 0, 1/16 exactly +-1, the rest spread evenly
    (a 1/32767 grid, so that paths also return exactly to earlier points)."""
    count = int(np.prod(shape))
    raw = np.frombuffer(draw(st.binary(min_size=3 * count, max_size=3 * count)), dtype=np.uint8).reshape(count, 3)
    value = np.clip(raw[:, :2].copy().view("<i2")[:, 0] / 32767.0, -1.0, 1.0)
    control = raw[:, 2]
    value = np.where(control < _EDGE_BELOW, np.where(value < 0, -1.0, 1.0), value)
    value = np.where(control < _ZERO_BELOW, 0.0, value)
    return value.reshape(shape)


@st.composite
def displacement_paths(draw, dims: int, scale: float, n: int | None = None, min_steps: int = 2, max_steps: int = 30):
    """A random walk of relative displacements starting next to zero.

    Shape (steps, dims), or (steps, n, dims) when ``n`` is given. Each path has its own amplitude,
    drawn log-uniformly from 0.1 to 20 times ``scale``, so that one run of examples covers paths
    that stay elastic and paths that slip or yield far; steps reverse at random. About one
    increment in eight is exactly zero (a trial at the committed point, or motion along one axis,
    where laws have their kinks) and one in sixteen a full +-1 times the amplitude.
    """
    steps = draw(st.integers(min_steps, max(min_steps, max_steps)))
    amplitude = scale * 10.0 ** draw(st.floats(-1.0, 1.3))
    shape = (steps, dims) if n is None else (steps, n, dims)
    return amplitude * np.cumsum(draw(unit_arrays(shape)), axis=0)


@st.composite
def closed_cycles(draw, dims: int, scale: float, max_steps: int = 20):
    """A displacement path out from zero and back along the same points to exactly zero."""
    out = draw(displacement_paths(dims, scale, min_steps=2, max_steps=max_steps))
    return np.concatenate([out, out[-2::-1], np.zeros((1, dims))])


def _between(units: np.ndarray, low: float, high: float) -> np.ndarray:
    """Map ``[-1, 1]`` onto ``[low, high]`` (the edges exactly)."""
    return np.where(units <= -1.0, low, np.where(units >= 1.0, high, low + 0.5 * (units + 1.0) * (high - low)))


def normal_force_histories(steps: int, low: float = 1e5, high: float = 4e6, n: int | None = None):
    """Compressive normal forces (newtons), shape (steps,) or (steps, n), each within [low, high]."""
    shape = (steps,) if n is None else (steps, n)
    return unit_arrays(shape).map(lambda units: _between(units, low, high))


def contact_force_histories(steps: int, low: float = 1e5, high: float = 4e6, n: int | None = None, tension: bool = True):
    """Normal forces that also lose contact: within [low, high], exactly 0 (uplift, as the kernel
    passes it) or, with ``tension``, negative down to ``-high`` (a friction law must treat
    ``N < 0`` passed directly as no contact; the kernel itself clamps ``N`` at zero)."""
    shape = (steps,) if n is None else (steps, n)

    def build(pair):
        units, kind = pair
        forces = _between(units, low, high)
        forces = np.where(kind < -0.5, 0.0, forces)  # about a quarter lose contact
        if tension:
            forces = np.where((kind < -0.5) & (units < 0), -np.abs(units) * high, forces)
        return forces

    return st.tuples(unit_arrays(shape), unit_arrays(shape)).map(build)


@st.composite
def velocity_histories(draw, steps: int, dims: int, scale: float = 0.1, n: int | None = None):
    """Relative velocities (m/s), shape (steps, dims) or (steps, n, dims), not tied to any path.

    Each history has its own magnitude, drawn log-uniformly from 0.01 to 10 times ``scale``; the
    components (with exact zeros: at rest, or moving along one axis) are in ``[-1, 1]`` times
    that. A law that uses the velocity must accept any velocity with any path: the kernel's
    velocity comes from the integrator, not from the law's own history.
    """
    magnitude = scale * 10.0 ** draw(st.floats(-2.0, 1.0))
    shape = (steps, dims) if n is None else (steps, n, dims)
    return magnitude * draw(unit_arrays(shape))


@st.composite
def histories(
    draw,
    dims: int,
    scale: float,
    n: int = 1,
    max_steps: int = 30,
    low: float = 1e5,
    high: float = 4e6,
    contact: bool = False,
    tension: bool = False,
    velocity_scale: float | None = None,
):
    """``(path, normal, velocity)`` drawn together: (steps, n, dims), (steps, n), and (steps, n, dims)
    or None (without ``velocity_scale``).

    The same distributions as :func:`displacement_paths`, :func:`normal_force_histories` (with
    ``contact``: :func:`contact_force_histories`) and :func:`velocity_histories`, from one block of
    bytes: the conformance kit draws thousands of these, and each separate draw costs hypothesis
    a few milliseconds.
    """
    steps = draw(st.integers(2, max(2, max_steps)))
    sizes = [2, steps * n * dims, steps * n, steps * n if contact else 0, steps * n * dims if velocity_scale else 0]
    units = draw(unit_arrays((sum(sizes),)))
    parts = np.split(units, np.cumsum(sizes)[:-1])
    amplitude = scale * 10.0 ** (-1.0 + 1.15 * (parts[0][0] + 1.0))  # 0.1 to 20 times scale
    path = amplitude * np.cumsum(parts[1].reshape(steps, n, dims), axis=0)
    normal = _between(parts[2].reshape(steps, n), low, high)
    if contact:  # as contact_force_histories
        kind, units = parts[3].reshape(steps, n), parts[2].reshape(steps, n)
        normal = np.where(kind < -0.5, 0.0, normal)
        if tension:
            normal = np.where((kind < -0.5) & (units < 0), -np.abs(units) * high, normal)
    velocity = None
    if velocity_scale:
        magnitude = velocity_scale * 10.0 ** (-2.0 + 1.5 * (parts[0][1] + 1.0))  # 0.01 to 10 times the scale
        velocity = magnitude * parts[4].reshape(steps, n, dims)
    return path, normal, velocity


def _real_in(bounds, typical):
    low, high, low_open, high_open = bounds
    if low is not None and high is not None:
        # No subnormal values: their products underflow, so they are nobody's parameter.
        return st.floats(low, high, exclude_min=low_open, exclude_max=high_open, allow_subnormal=False)
    centre = abs(typical) if typical else 1.0
    # An open range: draw the magnitude log-uniformly over two decades around the typical value.
    magnitude = st.floats(-1.0, 1.0).map(lambda e: centre * 10.0**e)
    if low is not None:
        return magnitude.map(lambda m: low + m).filter(lambda v: v > low or (v == low and not low_open))
    if high is not None:
        return magnitude.map(lambda m: high - m).filter(lambda v: v < high or (v == high and not high_open))
    return st.tuples(magnitude, st.sampled_from([-1.0, 1.0])).map(lambda t: t[0] * t[1])


@st.composite
def law_parameters(draw, law_class: type, **fixed):
    """Keyword parameters for ``law_class`` drawn within each parameter's declared range.

    Works for attrs classes whose real parameters are :func:`bearingfw.parameter` fields; fields
    with defaults and no declared range keep their default. ``fixed`` overrides any parameter
    with a value or a strategy. Combinations the class rejects (cross-parameter checks) are
    discarded.
    """
    params = {}
    for field in attrs.fields(law_class):
        if field.name in fixed:
            value = fixed[field.name]
            params[field.name] = draw(value) if isinstance(value, st.SearchStrategy) else value
        elif "bounds" in field.metadata:
            params[field.name] = draw(_real_in(field.metadata["bounds"], field.metadata.get("typical")))
        elif field.default is attrs.NOTHING:
            raise ValueError(f"{law_class.__name__}: no range declared for required parameter {field.name!r}; pass it")
    try:
        law_class(**params)
    except ParameterError:
        assume(False)
    return params


def laws(law_class: type, **fixed):
    """Law instances of ``law_class`` with parameters from :func:`law_parameters`."""
    return law_parameters(law_class, **fixed).map(lambda params: law_class(**params))


def per_bearing_fields(law_or_class) -> list[str]:
    """The names of the parameters of an attrs law class made with ``parameter(..., per_bearing=True)``."""
    cls = law_or_class if isinstance(law_or_class, type) else type(law_or_class)
    if not attrs.has(cls):
        return []
    return [field.name for field in attrs.fields(cls) if field.metadata.get("per_bearing")]


def _near(field, value):
    """Values of a parameter around ``value``: within a quarter of a bounded range either side, or
    within a factor of two of it for an open range (a typical draw where ``value`` is 0), always
    inside the declared range."""
    low, high, low_open, high_open = field.metadata["bounds"]

    def inside(v):
        above = low is None or v > low or (v == low and not low_open)
        return above and (high is None or v < high or (v == high and not high_open))

    if value is None or not np.isfinite(value):
        return _real_in(field.metadata["bounds"], field.metadata.get("typical"))
    if low is not None and high is not None:
        width = 0.25 * (high - low)
        candidates = st.floats(max(low, value - width), min(high, value + width))
    elif value != 0:
        candidates = st.floats(-0.3, 0.3).map(lambda e: value * 10.0**e)
    else:
        candidates = _real_in(field.metadata["bounds"], field.metadata.get("typical"))
    return st.one_of(st.just(value), candidates).filter(inside)


@st.composite
def per_bearing_laws(draw, law, n: int = 3, built: bool = True, near: bool = True):
    """``(array_law, [law_0, ..., law_{n-1}])``: ``n`` laws of ``law``'s class with parameters drawn
    by :func:`law_parameters` (the other fields, ``dims`` included, as in ``law``), and the one law
    that holds them as per-bearing arrays (a parameter equal across the ``n`` stays a scalar, as the
    kernel does). Each connector of the array law must respond as its own law alone.

    ``near`` (default) draws each per-bearing parameter around ``law``'s own value (within a
    quarter of a bounded range, a factor of two of an open one, or exactly it), so that the laws
    keep the scales (and the cost) of ``law``; ``near=False`` draws over the whole ranges.

    ``built=False`` gives the keyword parameters instead of the laws, ``(dict, [dict, ...])``, so
    that the caller sees it if the class refuses the arrays (a cross-parameter check that cannot
    take them).
    """
    cls = type(law)
    names = per_bearing_fields(cls)
    others = {field.name: getattr(law, field.name) for field in attrs.fields(cls) if field.name not in names and field.init}
    around = {}
    if near:
        for field in attrs.fields(cls):
            value = getattr(law, field.name)
            if field.name in names and "bounds" in field.metadata and not isinstance(value, np.ndarray):
                around[field.name] = _near(field, value)
    singles = [draw(law_parameters(cls, **others, **around)) for _ in range(n)]
    combined = dict(others)
    for name in names:
        values = [params[name] for params in singles]
        if all(value == values[0] for value in values):
            combined[name] = values[0]
        else:
            combined[name] = np.asarray(values, dtype=float)
    if not built:
        return combined, singles
    return cls(**combined), [cls(**params) for params in singles]


__all__ = [
    "closed_cycles",
    "unit_arrays",
    "contact_force_histories",
    "displacement_paths",
    "histories",
    "law_parameters",
    "laws",
    "normal_force_histories",
    "per_bearing_fields",
    "per_bearing_laws",
    "velocity_histories",
]
