"""Purity in the runner: a law must leave the committed state it is given untouched.

The transient solver calls a law's ``respond`` many times from the same committed state (Newton
iterations, step halvings) and keeps the state of the converged call only. A law that changes the
state it is given in place therefore computes its next answers from a state that was never
committed: the run goes on to the end, with results off by any amount. The conformance kit
(:mod:`bearingfw.testing`) checks this thoroughly; the runner checks it cheaply before each cell's
analysis, under the cell's time limit (:func:`law_purity_problems`, some milliseconds): for each
law group, from the initial state and from the states after a few random steps, ``respond`` is
called twice on the same state, and a fingerprint of that
state (a hash of all its arrays) must not change, nor may the displacements and normal forces
it was given, nor may the two answers differ. The first call, at zero displacement from the
initial state, must also give no force (the protocol's "zero force at rest": every bearing starts
the analysis at rest, and a force there is a load the dead-load state was not computed with). A
cell whose law fails is recorded as failed (:class:`LawPurityError`), naming the law and its
bearings.
"""

from __future__ import annotations

import hashlib
from collections.abc import Mapping

import attrs
import numpy as np

__all__ = ["LawPurityError", "fingerprint", "law_purity_problems"]

#: Random steps after the initial state at which the check is repeated.
STEPS = 3
#: Displacement scale of the random steps (m) and the normal force given (N, compression).
DISPLACEMENT = 2e-3
NORMAL_FORCE = 1e5


class LawPurityError(RuntimeError):
    """A law changed the state it was given (or answered the same call differently)."""


def fingerprint(value) -> str:
    """SHA-256 over everything a law state holds: arrays (dtype, shape, bytes), mappings, sequences,
    attrs objects, scalars."""
    digest = hashlib.sha256()
    _feed(digest, value)
    return digest.hexdigest()


def _feed(digest, value) -> None:
    if isinstance(value, np.ndarray):
        digest.update(f"a{value.dtype.str}{value.shape}".encode())
        digest.update(np.ascontiguousarray(value).tobytes() if value.dtype != object else repr(value.tolist()).encode())
    elif isinstance(value, Mapping):
        digest.update(b"{")
        for key in sorted(value, key=repr):
            digest.update(repr(key).encode())
            _feed(digest, value[key])
        digest.update(b"}")
    elif isinstance(value, list | tuple):
        digest.update(b"(" if isinstance(value, tuple) else b"[")
        for item in value:
            _feed(digest, item)
        digest.update(b")")
    elif attrs.has(type(value)):
        _feed(digest, {f.name: getattr(value, f.name) for f in attrs.fields(type(value))})
    elif hasattr(value, "__dict__") and not isinstance(value, type):
        _feed(digest, vars(value))
    else:
        digest.update(repr(value).encode())


#: A force at rest up to this fraction of the forces of the random steps is round-off.
AT_REST = 1e-12


def _respond(group, state, u, normal, dt):
    """``respond`` given ``u`` and ``normal`` themselves (the kernel's own arrays are what a law could
    change), and whether it changed them."""
    given = (u.copy(), normal.copy())
    if group.velocity:
        response = group.law.respond(state, u, normal, dt, velocity=np.zeros_like(u))
    else:
        response = group.law.respond(state, u, normal, dt)
    return response, not (np.array_equal(u, given[0]) and np.array_equal(normal, given[1]))


def _same_answer(a, b) -> bool:
    return all(np.array_equal(np.asarray(x, dtype=float), np.asarray(y, dtype=float), equal_nan=True)
               for x, y in ((a.force, b.force), (a.tangent, b.tangent)))


def law_purity_problems(system, model, dt: float, seed: int = 0) -> list[str]:
    """What the cheap purity check (module docstring) finds wrong with the laws of ``system`` (the
    :class:`~bearingfw.model.System` of ``model``), one line per law; [] if nothing. A law that
    raises here is left to the analysis (which reports it with its own message)."""
    rng = np.random.default_rng(seed)
    problems = []
    for group in system.connectors.groups:
        if group.gap:  # the kernel's own compression-only gap: stateless
            continue
        law, n = group.law, group.n
        bearings = ", ".join(model.connectors[int(k)].name for k in group.connectors)
        who = f"law {getattr(law, 'name', type(law).__name__)!r} (bearings {bearings})"
        normal = np.full(n, NORMAL_FORCE)
        try:
            state = law.initial_state(n)
            at_rest, largest = None, 0.0
            for step in range(STEPS + 1):
                u = rng.normal(scale=DISPLACEMENT, size=(n, group.dims)) if step else np.zeros((n, group.dims))
                before = fingerprint(state)
                first, changed_inputs = _respond(group, state, u, normal.copy(), dt)
                if changed_inputs:
                    problems.append(f"{who} changed the displacements or normal forces it was given in respond (step "
                                    f"{step} of the purity check): they are the solver's own arrays, and respond must "
                                    "leave them untouched, or the analysis goes on from values nobody computed")
                    break
                if fingerprint(state) != before:
                    problems.append(f"{who} changed the committed state it was given in respond (step {step} of "
                                    "the purity check): respond must return a new state and leave its input "
                                    "untouched, or the solver's retries compound and the results are wrong")
                    break
                second, _ = _respond(group, state, u.copy(), normal.copy(), dt)
                if not _same_answer(first, second):
                    problems.append(f"{who} answered the same respond call from the same state differently (step "
                                    f"{step} of the purity check): it keeps state outside its state argument")
                    break
                force = np.abs(np.asarray(first.force, dtype=float))
                if step:
                    largest = max(largest, float(force.max(initial=0.0)))
                else:
                    at_rest = float(force.max(initial=0.0))
                state = first.state
            else:
                if at_rest is not None and at_rest > AT_REST * largest:
                    problems.append(f"{who} gives a force of {at_rest:.6g} N at zero displacement from its initial state "
                                    f"(N = {NORMAL_FORCE:g} N): a law must give no force at rest (every bearing starts "
                                    "the analysis at rest, and the dead-load state was computed without that force)")
        except Exception:  # noqa: BLE001 - a law that raises is the analysis's to report
            continue
    return problems
