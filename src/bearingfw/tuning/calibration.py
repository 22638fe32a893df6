"""Step 1 of the paper's tuning: least-squares calibration of model parameters against measured modes.

The model is rebuilt for each trial value of the variables (any parameter a ``build`` callable
turns into a :class:`~bearingfw.model.Model`: the stick stiffness K_s of the sliding bearings,
a modulus, a mass, ...). Each trial runs a modal analysis, pairs its modes with the
measurements (:mod:`bearingfw.tuning.pairing`; again at every trial, so modes that change
order are still paired right) and returns the weighted relative frequency errors::

    r_i = w_i (f_i(p) - f_i^measured) / f_i^measured

which :func:`scipy.optimize.least_squares` minimises within the variables' bounds (``sum r_i^2``;
the paper's "least square method" over its four frequencies). Each variable is searched as
``x = 1 + s``, ``s`` its place in its range from 0 at ``low`` to 1 at ``high``: in ``log p`` when
the lower bound is positive (stiffnesses span decades), else in ``p``.

Why so: the Jacobian is computed here, by forward differences with a fixed step
:data:`JACOBIAN_STEP` in ``x`` (backward at the upper bound, so no trial leaves the bounds), and
trials are cached by their exact values. A step relative to the variable (scipy's ``diff_step``) and the
trust region scipy starts with both scale with ``|x|``: were ``x`` zero at a bound, a start on the
bound (where a scan often ends) would give a zero Jacobian and a zero first step, and the fit
would never leave it. With ``x`` between 1 and 2, both are of the order of the range.

The :class:`CalibrationReport` holds the fitted values, the paired frequencies and errors before
(at the initial values) and after, and the MAC table of the paired shapes before against after
(the paper checks that tuning leaves the shapes unchanged) and the AutoMAC after.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import attrs
import numpy as np
from scipy.optimize import least_squares

from bearingfw.analysis import ModalResult, automac, mac, solve_modal
from bearingfw.model import Model
from bearingfw.parameters import ParameterError
from bearingfw.tuning.pairing import (
    Measurement,
    Observation,
    Pairing,
    PairingError,
    as_measurements,
    pair_modes,
    paired_shapes,
)

__all__ = ["BOUND_SNAP", "JACOBIAN_STEP", "CalibrationReport", "Variable", "calibrate", "evaluate"]

#: Residual of a measurement that finds no computed mode at a trial point (a 100 % error).
_UNPAIRED = 1.0
#: Finite-difference step of the Jacobian in the scaled variables: 1e-5 of a variable's range (in
#: log p or p). Far above the eigensolver's round-off (~1e-12 relative), far below the scale on
#: which the frequencies curve.
JACOBIAN_STEP = 1e-5
#: A fitted variable this close to a bound (in the scaled variable, 1e-8 of its range) is on it.
BOUND_SNAP = 1e-8


@attrs.frozen
class Variable:
    """A calibration variable: its start value and bounds (``low < high``, start within)."""

    name: str
    initial: float
    low: float
    high: float

    def __attrs_post_init__(self):
        values = (self.initial, self.low, self.high)
        if not all(isinstance(v, (int, float)) and math.isfinite(v) for v in values):
            raise ParameterError(f"calibrate: variable {self.name!r} needs finite (initial, low, high), got {values}")
        if not self.low < self.high or not self.low <= self.initial <= self.high:
            raise ParameterError(
                f"calibrate: variable {self.name!r} must have low < high and low <= initial <= high, got "
                f"initial = {self.initial:g}, low = {self.low:g}, high = {self.high:g}"
            )

    @property
    def logarithmic(self) -> bool:
        return self.low > 0

    def to_x(self, value: float) -> float:
        """The variable of the least squares (module docstring): 1 at ``low``, 2 at ``high``."""
        if self.logarithmic:
            return 1.0 + math.log(value / self.low) / math.log(self.high / self.low)
        return 1.0 + (value - self.low) / (self.high - self.low)

    def from_x(self, x: float) -> float:
        if x <= 1.0 or x >= 2.0:  # exactly the bound, not exp(log(.)) of it
            return self.low if x <= 1.0 else self.high
        if self.logarithmic:
            value = self.low * math.exp((x - 1.0) * math.log(self.high / self.low))
        else:
            value = self.low + (x - 1.0) * (self.high - self.low)
        return min(max(value, self.low), self.high)


def _on_bounds(x: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """``x`` with each variable that stopped within :data:`BOUND_SNAP` of a bound put on it.

    Why: a bounded least squares keeps its iterates strictly inside (scipy's trust region
    reflective), so an optimum on a bound comes back a hair inside it (``399999999.7`` for a
    bound of 4e8); a value on its bound is what a constrained fit means and what users compare.
    """
    x = np.asarray(x, dtype=float)
    return np.where(upper - x <= BOUND_SNAP, upper, np.where(x - lower <= BOUND_SNAP, lower, x))


def _variables(variables: Mapping[str, Sequence[float]]) -> tuple[Variable, ...]:
    if not isinstance(variables, Mapping) or not variables:
        raise ParameterError("calibrate: 'variables' must map at least one name to (initial, low, high)")
    out = []
    for name, spec in variables.items():
        try:
            initial, low, high = (float(v) for v in spec)
        except (TypeError, ValueError):
            raise ParameterError(f"calibrate: variable {name!r} must be (initial, low, high), got {spec!r}") from None
        out.append(Variable(str(name), initial, low, high))
    return tuple(out)


@attrs.frozen(eq=False)
class CalibrationReport:
    """Outcome of :func:`calibrate` (module docstring); :meth:`to_dict` is its JSON form."""

    variables: tuple[Variable, ...]
    values: dict[str, float]
    before: Pairing
    after: Pairing
    modal_before: ModalResult
    modal_after: ModalResult
    mac_before_after: np.ndarray | None
    automac_after: np.ndarray
    cost: float
    evaluations: int
    success: bool
    message: str

    @property
    def measurements(self) -> tuple[Measurement, ...]:
        return self.after.measurements

    @property
    def initial(self) -> dict[str, float]:
        return {v.name: v.initial for v in self.variables}

    @property
    def errors_before(self) -> np.ndarray:
        return self.before.errors

    @property
    def errors_after(self) -> np.ndarray:
        return self.after.errors

    def to_dict(self) -> dict[str, Any]:
        """The JSON form: per mode the frequency, error and label at the variables' ``initial`` values
        (``start``, ``error_start``, ``label_start``: where the least squares began) and ``after``.
        ("before" is left to the commands, for the model before tuning.)"""

        def matrix(a):
            return None if a is None else np.round(a, 6).tolist()

        return {
            "variables": {
                v.name: {"initial": v.initial, "fitted": self.values[v.name], "low": v.low, "high": v.high}
                for v in self.variables
            },
            "pairing": self.after.by,
            "modes": [
                {
                    "name": m.name,
                    "measured": m.frequency,
                    "start": float(fb),
                    "after": float(fa),
                    "error_start": float(eb),
                    "error_after": float(ea),
                    "label_start": lb,
                    "label_after": la,
                }
                for m, fb, fa, eb, ea, lb, la in zip(
                    self.measurements, self.before.frequencies, self.after.frequencies, self.errors_before,
                    self.errors_after, self.before.labels, self.after.labels, strict=True,
                )
            ],
            "mac_start_after": matrix(self.mac_before_after),
            "automac_after": matrix(self.automac_after),
            "cost": self.cost,
            "evaluations": self.evaluations,
            "success": self.success,
            "message": self.message,
        }


def _call(build: Callable, variables: tuple[Variable, ...], values: Sequence[float]) -> Model:
    # One variable: build(value); several: build({name: value}).
    if len(variables) == 1:
        model = build(values[0])
    else:
        model = build({v.name: val for v, val in zip(variables, values, strict=True)})
    if not isinstance(model, Model):
        raise ParameterError(f"calibrate: 'build' must return a Model, got {type(model).__name__}")
    return model


def evaluate(
    model: Model,
    measured,
    *,
    by: str = "label",
    observation: Observation | None = None,
    n_modes: int = 30,
    **modal_options,
) -> tuple[ModalResult, Pairing]:
    """One modal analysis of ``model`` and its pairing with ``measured``."""
    modal = solve_modal(model, n_modes, **modal_options)
    return modal, pair_modes(modal, measured, by=by, observation=observation)


def calibrate(
    build: Callable[[Any], Model],
    measured,
    variables: Mapping[str, Sequence[float]],
    *,
    by: str = "label",
    observation: Observation | None = None,
    n_modes: int = 30,
    weights: Sequence[float] | None = None,
    max_evaluations: int = 100,
    tolerance: float = 1e-8,
    **modal_options,
) -> CalibrationReport:
    """Fit ``variables`` so that ``build(...)``'s modes match ``measured`` in the least-squares sense.

    ``build`` takes the value of the single variable, or a ``{name: value}`` dict when there
    are several. ``measured``: see :func:`bearingfw.tuning.as_measurements`. ``variables``:
    ``{name: (initial, low, high)}``. ``weights`` (one per measurement, default 1) scale the
    relative errors. ``n_modes`` computed modes must include every measured one.
    ``max_evaluations`` bounds the modal analyses of the least squares (about: scipy counts
    iterations, each one analysis and a Jacobian of one per variable); the report's
    ``evaluations`` is how many it ran. Extra keywords go to
    :func:`bearingfw.analysis.solve_modal` (e.g. ``registry``).
    """
    ms = as_measurements(measured)
    vs = _variables(variables)
    w = np.ones(len(ms)) if weights is None else np.asarray(weights, dtype=float)
    if w.shape != (len(ms),) or not np.all(np.isfinite(w)) or np.any(w < 0):
        raise ParameterError(f"calibrate: 'weights' must be {len(ms)} finite values >= 0, got {weights!r}")
    target = np.array([m.frequency for m in ms])
    # keyed by the exact trial values: two trials a finite-difference step apart are two analyses
    cache: dict[tuple[float, ...], tuple[ModalResult, Pairing] | None] = {}

    def run(x) -> tuple[ModalResult, Pairing] | None:
        key = tuple(float(xi) for xi in np.asarray(x, dtype=float))
        if key not in cache:
            values = [v.from_x(xi) for v, xi in zip(vs, key, strict=True)]
            try:
                cache[key] = evaluate(
                    _call(build, vs, values), ms, by=by, observation=observation, n_modes=n_modes, **modal_options
                )
            except PairingError:
                cache[key] = None
        return cache[key]

    def residuals(x) -> np.ndarray:
        result = run(x)
        if result is None:
            return w * _UNPAIRED
        return w * (result[1].frequencies / target - 1.0)

    lower = np.array([v.to_x(v.low) for v in vs])
    upper = np.array([v.to_x(v.high) for v in vs])

    def jacobian(x) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        at = residuals(x)  # cached: the least squares has just evaluated x
        columns = []
        for j in range(len(vs)):
            # a forward step, backward where it would cross the upper bound: every trial within the bounds
            step = x.copy()
            step[j] = x[j] + JACOBIAN_STEP if x[j] + JACOBIAN_STEP <= upper[j] else x[j] - JACOBIAN_STEP
            columns.append((residuals(step) - at) / (step[j] - x[j]))
        return np.column_stack(columns)

    x0 = np.array([v.to_x(v.initial) for v in vs])
    start = run(x0)
    if start is None:  # raise the pairing error with its message
        evaluate(_call(build, vs, [v.initial for v in vs]), ms, by=by, observation=observation, n_modes=n_modes,
                 **modal_options)
    analyses = len(cache)
    # max_evaluations bounds the modal analyses: each iteration costs one and a Jacobian one per variable
    fit = least_squares(
        residuals, x0, jac=jacobian, bounds=(lower, upper), xtol=tolerance, ftol=tolerance, gtol=tolerance,
        max_nfev=max(1, max_evaluations // (1 + len(vs))),
    )
    x_end = _on_bounds(fit.x, lower, upper)
    end = run(x_end)
    if end is not None and not np.array_equal(x_end, fit.x):
        inside = run(fit.x)
        if inside is not None and np.sum(residuals(x_end) ** 2) > np.sum(residuals(fit.x) ** 2) * (1 + 1e-9):
            x_end, end = fit.x, inside  # the bound is no better: keep where the least squares stopped
    analyses = len(cache) - analyses
    if end is None:
        end = start
    (modal0, pair0), (modal1, pair1) = start, end
    before_shapes = paired_shapes(modal0, pair0, observation)
    after_shapes = paired_shapes(modal1, pair1, observation)
    same_dofs = before_shapes.shape == after_shapes.shape
    return CalibrationReport(
        variables=vs,
        values={v.name: v.from_x(xi) for v, xi in zip(vs, x_end, strict=True)},
        before=pair0,
        after=pair1,
        modal_before=modal0,
        modal_after=modal1,
        mac_before_after=mac(before_shapes, after_shapes) if same_dofs else None,
        automac_after=automac(after_shapes),
        cost=float(fit.cost),
        evaluations=analyses,
        success=bool(fit.success),
        message=str(fit.message),
    )
