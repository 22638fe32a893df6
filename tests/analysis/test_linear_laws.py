"""Linear laws folded into the factorised matrix (protocol flag ``linear``, issue 16): a run whose laws
are all linear solves each step in one back-substitution, with no law call, and gives what Newton on
the same laws gives; a run with any nonlinear law is not folded; a law that claims ``linear`` falsely
fails the conformance kit."""

from __future__ import annotations

import attrs
import numpy as np
import pytest
from kernel_models import band_limited_noise, deck_model

from bearingfw.analysis import ConnectorResponse, ElementForces, Rayleigh, gravity, hht, solve_transient
from bearingfw.analysis.excitation import SupportMotion, support_groups
from bearingfw.laws.elastic import Frictionless, LinearSpring
from bearingfw.model import build_system
from bearingfw.protocol import LawResponse
from bearingfw.testing import check_law

DT = 0.01


def _run(system, ground, calls: list):
    respond = type(system.connectors.groups[0].law).respond

    def counted(self, *args, **kwargs):
        calls.append(1)
        return respond(self, *args, **kwargs)

    cls = type(system.connectors.groups[0].law)
    cls.respond = counted
    try:
        return solve_transient(system, ground, DT, preload=gravity(system), damping=Rayleigh(0.21, 0.00208),
                               recorders=[ConnectorResponse(name="b"), ElementForces(["GA0", "GB3"], name="s")])
    finally:
        cls.respond = respond


def _compare(folded, newton):
    for key in ("b.force", "b.displacement", "b.law_displacement", "s"):
        assert np.array_equal(np.isnan(folded[key]), np.isnan(newton[key])), key  # NaN outside law directions
        scale = np.nanmax(np.abs(newton[key]))
        assert scale > 0, key
        assert np.nanmax(np.abs(folded[key] - newton[key])) <= 1e-9 * scale, key
    assert folded.stats["balance_error"] < 1e-9 and newton.stats["balance_error"] < 1e-9


@pytest.mark.parametrize(("law", "params", "cls"), [("linear-spring", {"k": 4e8}, LinearSpring),
                                                    ("frictionless", {}, Frictionless)])
def test_folded_linear_laws_equal_newton_on_them(law, params, cls, monkeypatch):
    system = build_system(deck_model(law, params))
    ag = band_limited_noise(301, DT, seed=3, amplitude=[3.0, 2.0, 1.0])
    folded_calls, newton_calls = [], []
    folded = _run(system, ag, folded_calls)
    monkeypatch.setattr(cls, "linear", False)
    monkeypatch.setattr(hht, "COMPILED_NEWTON", False)  # Newton through respond(), so that the calls are counted
    newton = _run(system, ag, newton_calls)
    _compare(folded, newton)
    assert folded.stats["iterations"] == 0 and newton.stats["iterations"] >= 300
    # the folded run calls the laws for its tangent and the preload only, not per step
    assert len(folded_calls) < 10 < 300 <= len(newton_calls)


def test_folded_linear_laws_under_differential_support_motion(monkeypatch):
    """The support motion's offset of the law displacements enters the right-hand side, ``-c B^T K_l e``."""
    system = build_system(deck_model("linear-spring", {"k": 2e8}))
    ag = band_limited_noise(201, DT, seed=5, amplitude=[3.0, 2.0, 1.0])
    groups = support_groups(system)
    delayed = {}
    for k, g in enumerate(groups):  # the wave reaches group k after 4 k steps
        delayed[g] = np.zeros_like(ag)
        delayed[g][4 * k:] = ag[: ag.shape[0] - 4 * k]
    motion = SupportMotion(groups, delayed, baseline="none")
    folded = _run(system, motion, [])
    monkeypatch.setattr(LinearSpring, "linear", False)
    newton = _run(system, motion, [])
    _compare(folded, newton)
    assert folded.stats["iterations"] == 0


def test_a_run_with_a_nonlinear_law_is_not_folded():
    coulomb = build_system(deck_model("regularized-coulomb", {"k": 4e8, "mu": 0.04}))
    spring = build_system(deck_model("linear-spring", {"k": 4e8}))
    for system, folded in ((coulomb, False), (spring, True)):
        p = hht.Problem(
            M=system.M_free, K=system.K_free, B=system.B_free, Bt=system.B_free.T.tocsr(), V=system.V_free,
            kv=system.connectors.kv, a0=0.0, a1=0.0, scheme=hht.Scheme(-0.05), ops=system.connectors,
            d0=np.zeros(system.B_free.shape[0]), f0=np.zeros(system.B_free.shape[0]),
            N0=np.full(system.connectors.kv.size, 1e5), force_floor=1.0, tol_force=1e-8, tol_displacement=1e-8,
            max_iterations=25, fast=True,
        )
        K = hht.linear_tangent(p, 0.005)
        assert (K is not None) == folded
        if folded:  # the laws' tangent: k on the diagonal of every governed direction
            assert np.array_equal(K, 4e8 * np.eye(p.m))


@attrs.frozen
class _StiffeningSpring(LinearSpring):
    """Claims ``linear`` but stiffens with the displacement."""

    def respond(self, state, u, normal_force, dt) -> LawResponse:
        r = super().respond(state, u, normal_force, dt)
        u = np.asarray(u, dtype=float)
        return LawResponse(r.force + 1e12 * u**3, r.tangent + 3e12 * (u**2)[..., None] * np.eye(self.dims), state)


def test_a_false_linear_claim_fails_the_conformance_kit():
    with pytest.raises(AssertionError, match="breaks property 'linear'"):
        check_law(_StiffeningSpring(k=4e8))
