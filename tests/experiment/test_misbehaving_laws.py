"""Laws that break the protocol in ways the runner must name, not absorb.

Found by an adversarial review: a law calling ``sys.exit(0)`` ended ``bearingfw run`` with exit
status 0 and no results; a law changing the displacements it is given in place was reported as a
convergence failure of the solver; a law with a force at rest ran to ``ok``.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
from tiny_experiment import write_tiny

from bearingfw.experiment import SerialExecutor, Store, load_experiment, run_experiment
from bearingfw.experiment.purity import law_purity_problems
from bearingfw.protocol import LawResponse

EXITING_LAW = '''
from typing import ClassVar
import attrs, numpy as np, bearingfw
from bearingfw.protocol import LawResponse

@attrs.frozen
class ExitingSpring:
    name: ClassVar[str] = "test-exiting-spring"
    rigid: ClassVar[bool] = False
    dims: int = 1
    def initial_state(self, n):
        return {}
    def respond(self, state, u, normal_force, dt):
        u = np.asarray(u, dtype=float)
        if np.any(np.abs(u) > 1e-9):
            raise SystemExit(0)  # the bug: a law that ends the process
        return LawResponse(4e8 * u, np.full((u.shape[0], self.dims, self.dims), 4e8), state)

@bearingfw.hookimpl
def bearingfw_register_laws():
    return [ExitingSpring]
'''


def test_a_law_calling_sys_exit_fails_its_cell_and_the_run_goes_on(tmp_path):
    (tmp_path / "plug").mkdir()
    (tmp_path / "plug" / "exiting_law.py").write_text(EXITING_LAW)
    spec = write_tiny(
        tmp_path / "spec", models=("M1",), levels=("D_0",),
        extra='[models.exit]\nlaw = "test-exiting-spring"\n',
        **{'plugins = ["bfw_test_laws"]': 'plugins = ["bfw_test_laws", "exiting_law"]',
           'python_path = [': f'python_path = ["{(tmp_path / "plug").as_posix()}", '},
    )
    summary = run_experiment(load_experiment(spec), tmp_path / "out", SerialExecutor())
    assert summary.exit_code == 1
    assert [c for c, _ in summary.failed] == ["exit/tremor/D_0"]
    assert "sys.exit(0) was called while the cell was computed" in summary.failed[0][1]
    store = Store(tmp_path / "out")
    assert store.read_cell("exit/tremor/D_0")["error"]["type"] == "SystemExit"
    assert store.read_cell("M1/tremor/D_0")["status"] == "ok"  # the other cells are computed and kept


class _Spring:
    """A 1-D linear spring; subclasses add the fault."""

    name = "test-spring"
    dims = 1

    def initial_state(self, n):
        return {}

    def respond(self, state, u, normal_force, dt):
        return LawResponse(4e8 * u, np.full((u.shape[0], 1, 1), 4e8), state)


class _ScalingInput(_Spring):
    name = "test-input-scaling-spring"

    def respond(self, state, u, normal_force, dt):
        u *= 1.0000001  # the bug: the solver's own displacements changed in place
        return super().respond(state, u, normal_force, dt)


class _Offset(_Spring):
    name = "test-offset-spring"

    def respond(self, state, u, normal_force, dt):
        response = super().respond(state, u, normal_force, dt)
        return LawResponse(response.force + 1e3, response.tangent, state)  # 1 kN at rest


def _problems(law) -> list[str]:
    group = SimpleNamespace(gap=False, law=law, n=2, connectors=[0, 1], dims=1, velocity=False)
    system = SimpleNamespace(connectors=SimpleNamespace(groups=[group]))
    model = SimpleNamespace(connectors=[SimpleNamespace(name="1A"), SimpleNamespace(name="1B")])
    return law_purity_problems(system, model, 0.01)


def test_a_sound_law_passes_the_runners_check():
    assert _problems(_Spring()) == []


def test_a_law_changing_the_displacements_it_is_given_is_named():
    (problem,) = _problems(_ScalingInput())
    assert problem.startswith("law 'test-input-scaling-spring' (bearings 1A, 1B) changed the displacements")


def test_a_law_with_a_force_at_rest_is_named():
    (problem,) = _problems(_Offset())
    assert problem.startswith("law 'test-offset-spring' (bearings 1A, 1B) gives a force of 1000 N at zero displacement")


class _Raising(_Spring):
    name = "test-raising-spring"

    def respond(self, state, u, normal_force, dt):
        if np.any(np.abs(u) > 1e-9):
            raise RuntimeError("boom")
        return super().respond(state, u, normal_force, dt)


def test_an_error_inside_a_law_names_the_law():
    from bearingfw.model.connectors import ConnectorOperators

    law = _Raising()
    group = SimpleNamespace(law=law, n=2, velocity=False)
    operators = SimpleNamespace(_calls=[(group, np.arange(2), (2, 1), np.arange(2))])
    try:
        ConnectorOperators.respond(operators, [{}], np.full(2, 1e-3), np.full(2, 1e5), 0.01)
    except RuntimeError as exc:
        assert str(exc) == "boom"  # the law's own exception, unchanged
        assert exc.__notes__ == ["raised by law 'test-raising-spring' in respond() (a group of 2 connector(s))"]
    else:
        raise AssertionError("the law's error was swallowed")


def test_a_cell_stopped_by_a_law_error_names_the_law(tmp_path):
    spec = write_tiny(tmp_path / "spec", models=("boom",), levels=("D_0",))
    summary = run_experiment(load_experiment(spec), tmp_path / "out", SerialExecutor())
    (cell, message), = summary.failed
    assert cell == "boom/tremor/D_0"
    assert "raised by law 'test-exploding-spring' in respond()" in message


def test_a_complex_force_is_refused_naming_the_law():
    import pytest

    from bearingfw.model import ModelError
    from bearingfw.model.connectors import _check_response

    group = SimpleNamespace(law=_Spring(), n=2, dims=1, coupling=False, velocity=False)
    sound = _Spring().respond({}, np.full((2, 1), 1e-3), np.full(2, 1e5), 0.01)
    _check_response(group, sound)
    _check_response(group, LawResponse(sound.force.astype(int), sound.tangent, {}))  # integers are real numbers
    with pytest.raises(ModelError, match=r"law 'test-spring': respond\(\) returned 'force' of dtype complex128"):
        _check_response(group, LawResponse(sound.force + 0j, sound.tangent, {}))
