"""Test-only bearing laws, loaded by experiments through ``plugins = ["bfw_test_laws"]``.

- ``test-exploding-spring``: a linear spring that raises as soon as it is displaced (a plugin bug):
  building the model, the gravity preload and the modal analysis (all at zero displacement) work,
  the first time step fails.
- ``test-slow-spring``: a linear spring that sleeps ``delay`` seconds in every call, so that a cell
  takes long enough for a test to kill the run in the middle.
- ``test-held-spring``: a linear spring that, in a process whose environment has ``BFW_TEST_HOLD``
  set, never returns once it is displaced (like ``test-blocking-spring``); elsewhere it is a plain
  spring. A test starts a run with the variable, so that its cells of this law are in flight for as
  long as the test wants, and computes the same cells at full speed without it (same digest).
- ``test-blocking-spring``: a linear spring whose ``respond`` never returns once it is displaced (a
  stuck plugin): the run's check works, the first time step hangs; for interrupts and time limits.
- ``test-deaf-spring``: like ``test-blocking-spring``, but it first makes its process ignore SIGALRM, as
  a law stuck in compiled code would not hear it: only the run ending its worker process stops it.
- ``test-noisy-spring``: a linear spring whose every call overflows a throw-away number (a numpy
  RuntimeWarning), for the warnings a cell reports.
- ``test-mutating-spring``: a linear spring that writes into the state it is given (an impure
  law): its force comes out right only the first time a state is used.
"""

from __future__ import annotations

import os
import time
from typing import ClassVar

import attrs
import numpy as np

import bearingfw
from bearingfw.parameters import dims_parameter, parameter
from bearingfw.protocol import LawResponse


def _spring(k: float, u, dims: int) -> LawResponse:
    u = np.asarray(u, dtype=float)
    tangent = np.broadcast_to(k * np.eye(dims), (u.shape[0], dims, dims)).copy()
    return LawResponse(k * u, tangent, None)


@attrs.frozen
class _TestSpring:
    """A linear spring (not declared ``linear``: the kernel calls it in every Newton iteration); each
    test law below changes only what happens before the spring answers (:meth:`_before`)."""

    rigid: ClassVar[bool] = False
    k: float = parameter(low=0.0, low_open=True, unit="N/m", default=4e8)
    dims: int = dims_parameter()

    def initial_state(self, n: int) -> dict:
        return {}

    def _before(self, u: np.ndarray) -> None:
        """What the test law does first (raise, sleep, block)."""

    def respond(self, state, u, normal_force, dt) -> LawResponse:
        self._before(np.asarray(u))
        response = _spring(self.k, u, self.dims)
        return LawResponse(response.force, response.tangent, state)


def _displaced(u: np.ndarray) -> bool:
    return bool(np.any(np.abs(u) > 1e-12))


@attrs.frozen
class ExplodingSpring(_TestSpring):
    name: ClassVar[str] = "test-exploding-spring"

    def _before(self, u):
        if _displaced(u):
            raise RuntimeError("test-exploding-spring: exploded on purpose")


@attrs.frozen
class SlowSpring(_TestSpring):
    name: ClassVar[str] = "test-slow-spring"
    delay: float = parameter(low=0.0, default=1e-3, unit="s")

    def _before(self, u):
        time.sleep(self.delay)


#: The environment variable that holds ``test-held-spring`` (read in the worker, at every call).
HOLD = "BFW_TEST_HOLD"


@attrs.frozen
class HeldSpring(_TestSpring):
    name: ClassVar[str] = "test-held-spring"

    def _before(self, u):
        while os.environ.get(HOLD) and _displaced(u):
            time.sleep(0.1)  # held in short sleeps until the process is killed


@attrs.frozen
class BlockingSpring(_TestSpring):
    name: ClassVar[str] = "test-blocking-spring"

    def _before(self, u):
        while _displaced(u):
            time.sleep(1.0)  # stuck for good, in short sleeps (a signal gets through between them)


@attrs.frozen
class DeafSpring(_TestSpring):
    name: ClassVar[str] = "test-deaf-spring"

    def _before(self, u):
        if _displaced(u):
            import signal

            # Ignored by the whole process: blocking SIGALRM in this thread only is not enough, the kernel
            # then hands it to another thread (numpy's BLAS threads) and Python still runs the cell's
            # handler here between two sleeps.
            signal.signal(signal.SIGALRM, signal.SIG_IGN)
            while True:
                time.sleep(1.0)


@attrs.frozen
class MutatingSpring(_TestSpring):
    name: ClassVar[str] = "test-mutating-spring"

    def initial_state(self, n: int) -> dict:
        return {"calls": np.zeros(n)}

    def respond(self, state, u, normal_force, dt) -> LawResponse:
        state["calls"] += 1.0  # the bug: the committed state is changed in place
        scale = 1.0 + state["calls"][:, None]
        response = _spring(self.k, u, self.dims)
        return LawResponse(response.force * scale, response.tangent, {"calls": state["calls"].copy()})


@attrs.frozen
class NoisySpring(_TestSpring):
    name: ClassVar[str] = "test-noisy-spring"

    def _before(self, u):
        np.exp(np.full(1, 1000.0))  # overflows: RuntimeWarning, result unused


@bearingfw.hookimpl
def bearingfw_register_laws():
    return [ExplodingSpring, SlowSpring, HeldSpring, BlockingSpring, DeafSpring, MutatingSpring, NoisySpring]
