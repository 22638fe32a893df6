"""Hypothesis strategies for bearing laws: displacement paths, normal forces, parameters."""

from __future__ import annotations

import attrs
import numpy as np
from hypothesis import assume
from hypothesis import strategies as st

from bearingfw.parameters import ParameterError


@st.composite
def displacement_paths(draw, dims: int, scale: float, n: int | None = None, min_steps: int = 2, max_steps: int = 30):
    """A random walk of relative displacements starting next to zero.

    Shape (steps, dims), or (steps, n, dims) when ``n`` is given. Each path has its own amplitude,
    drawn log-uniformly from 0.1 to 20 times ``scale``, so that one run of examples covers paths
    that stay elastic and paths that slip or yield far; steps reverse at random.
    """
    steps = draw(st.integers(min_steps, max_steps))
    amplitude = scale * 10.0 ** draw(st.floats(-1.0, 1.3))
    shape = (steps, dims) if n is None else (steps, n, dims)
    count = int(np.prod(shape))
    increments = draw(st.lists(st.floats(-1.0, 1.0), min_size=count, max_size=count))
    return amplitude * np.cumsum(np.reshape(increments, shape), axis=0)


@st.composite
def closed_cycles(draw, dims: int, scale: float):
    """A displacement path out from zero and back along the same points to exactly zero."""
    out = draw(displacement_paths(dims, scale, min_steps=2, max_steps=20))
    return np.concatenate([out, out[-2::-1], np.zeros((1, dims))])


def normal_force_histories(steps: int, low: float = 1e5, high: float = 4e6, n: int | None = None):
    """Compressive normal forces (newtons), shape (steps,) or (steps, n), each within [low, high]."""
    shape = (steps,) if n is None else (steps, n)
    count = int(np.prod(shape))
    values = st.lists(st.floats(low, high), min_size=count, max_size=count)
    return values.map(lambda v: np.reshape(np.asarray(v, dtype=float), shape))


def _real_in(bounds, typical):
    low, high, low_open, high_open = bounds
    if low is not None and high is not None:
        return st.floats(low, high, exclude_min=low_open, exclude_max=high_open)
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


__all__ = ["closed_cycles", "displacement_paths", "law_parameters", "laws", "normal_force_histories"]
