"""Simulated ambient vibration: the modal superposition is exact, sensors read absolute acceleration."""

from __future__ import annotations

import numpy as np
import pytest
from oma_systems import MASS, RAYLEIGH, chain_matrices, chain_modes, column_model, state_space_response
from scipy import signal

from bearingfw.analysis import NodalResponse, Rayleigh, TransientSettings, solve_modal, solve_transient
from bearingfw.oma import identify, modal_damping, simulate_ambient
from bearingfw.oma.simulate import modal_filters, modal_response
from bearingfw.parameters import ParameterError


@pytest.fixture(scope="module")
def column():
    return solve_modal(column_model(), 8)


def test_modal_superposition_equals_the_full_state_space_model():
    """All three modes of the classically damped chain: the two exact discretisations agree to round-off."""
    f, zeta, shapes = chain_modes()
    M, C, K = chain_matrices()
    phi = shapes / np.sqrt(MASS * np.sum(shapes**2, axis=0))  # mass-normalised
    gamma = phi.T @ M @ np.ones(3)
    dt = 0.02
    ground = np.random.default_rng(5).standard_normal(3000)
    modal = modal_response(2 * np.pi * f, zeta, -np.outer(ground, gamma), dt) @ phi.T + ground[:, None]
    full = state_space_response(M, C, K, ground, dt)
    np.testing.assert_allclose(modal, full, rtol=0, atol=1e-9 * np.abs(full).max())


def test_the_discrete_poles_are_exp_lambda_dt():
    omega, zeta, dt = np.array([3.0, 40.0]), np.array([0.02, 0.1]), 0.01
    _, a = modal_filters(omega, zeta, dt)
    lam = -zeta * omega + 1j * omega * np.sqrt(1 - zeta**2)
    for k in range(2):
        roots = np.roots(a[k])
        np.testing.assert_allclose(
            sorted(roots, key=np.imag),
            sorted([np.exp(lam[k] * dt), np.exp(np.conj(lam[k]) * dt)], key=np.imag),
            rtol=1e-12,
        )


def test_sensors_read_absolute_acceleration(column):
    """At the clamped base a sensor reads the ground; ground along x leaves the y channels at rest."""
    ground = np.zeros((2001, 3))
    ground[:, 0] = 0.1 * np.random.default_rng(7).standard_normal(2001)
    data = simulate_ambient(column, ["C0.ux", "C6.ux", "C6.uy"], 20.0, 0.01, ground_acceleration=ground, noise=0.0)
    np.testing.assert_array_equal(data.data[:, 0], ground[:, 0])
    assert np.std(data.data[:, 1]) > 2 * np.std(data.data[:, 0])  # the top amplifies its modes
    assert np.max(np.abs(data.data[:, 2])) < 1e-9 * np.max(np.abs(data.data[:, 1]))  # round-off in the shapes
    assert data.synthetic and "SYNTHETIC" in data.source and data.metadata["ground_rms"] == "given"
    drawn = simulate_ambient(column, ["C0.ux"], 20.0, 0.01, ground=(0.1, 0.0, 0.0), noise=0.0)
    assert np.std(drawn.data[:, 0]) == pytest.approx(0.1, rel=0.05) and drawn.metadata["seed"] == 0
    with pytest.raises(ParameterError, match="ground_acceleration"):
        simulate_ambient(column, ["C0.ux"], 20.0, 0.01, ground_acceleration=ground[:-1])


def test_the_same_input_through_the_transient_solver_gives_the_same_histories():
    """The column under a held support acceleration, once by modal superposition, once by HHT (alpha = 0) at a
    step ten times finer, its absolute accelerations recorded; both low-passed to 5 Hz (the two lowest modes).

    They agree within a few per cent (the solver's input is linear between its samples, a step of dt / 10
    here, where the simulation holds it: a lag of dt / 20), correlation > 0.998. A wrong sign of the
    support load (``+ Gamma a_g``) gives a negative correlation.
    """
    model = column_model()
    modal = solve_modal(model, 12)
    dt, steps, fine = 0.01, 601, 10
    ground = np.random.default_rng(0).standard_normal((steps, 3)) * [0.1, 0.05, 0.0]
    rayleigh = Rayleigh(0.2, 0.002)
    channels = ["C6.ux", "C6.uy", "C3.ux", "C3.uy"]
    simulated = simulate_ambient(
        modal, channels, (steps - 1) * dt, dt, damping=rayleigh, ground_acceleration=ground, noise=0.0
    ).data
    held = np.repeat(ground, fine, axis=0)[: (steps - 1) * fine + 1]
    recorder = NodalResponse(("C6", "C3"), quantity="acceleration", components=("ux", "uy"), total=True, name="acc")
    result = solve_transient(
        model, held, dt / fine, damping=rayleigh, settings=TransientSettings(alpha=0.0), recorders=[recorder]
    )
    solved = result["acc"][::fine].reshape(steps, -1)  # C6.ux, C6.uy, C3.ux, C3.uy
    low = signal.butter(6, 5.0, fs=1 / dt, output="sos")
    for j, name in enumerate(channels):
        a, b = signal.sosfiltfilt(low, simulated[:, j]), signal.sosfiltfilt(low, solved[:, j])
        assert np.std(a - b) < 0.05 * np.std(b), name
        assert np.corrcoef(a, b)[0, 1] > 0.998, name


def test_measurement_noise_and_seeds(column):
    clean = simulate_ambient(column, ["C6.ux"], 30.0, 0.01, noise=0.0)
    noisy = simulate_ambient(column, ["C6.ux"], 30.0, 0.01, noise=0.1)
    other = simulate_ambient(column, ["C6.ux"], 30.0, 0.01, noise=0.0, seed=1)
    ratio = np.std(noisy.data - clean.data) / np.std(clean.data)
    assert ratio == pytest.approx(0.1, rel=0.05)
    assert not np.allclose(other.data, clean.data)


def test_loads_excite_through_the_shapes(column):
    """A force along y at the top, no ground motion: only the y-bending modes answer."""
    data = simulate_ambient(column, ["C6.ux", "C6.uy"], 20.0, 0.01, ground=(0, 0, 0), loads={"C6.uy": 100.0}, noise=0)
    assert np.max(np.abs(data.data[:, 0])) < 1e-9 * np.max(np.abs(data.data[:, 1]))


def test_modal_damping_of_a_model_without_bearings_is_rayleighs_ratio(column):
    rayleigh = Rayleigh(0.2, 0.002)
    np.testing.assert_allclose(
        modal_damping(column, rayleigh), [rayleigh.ratio(f) for f in column.frequencies], rtol=1e-9
    )


def test_simulated_column_is_identified(column):
    """The model's own modes come back: the two bending modes of the column at its top and middle."""
    channels = ["C3.ux", "C3.uy", "C6.ux", "C6.uy"]
    data = simulate_ambient(
        column, channels, 300.0, 0.02, damping=RAYLEIGH.ratio(2.0), ground=(0.05, 0.05, 0.0), seed=4
    )
    found = identify(data).modes.frequencies
    for f in column.frequencies[:2]:
        assert np.min(np.abs(found / f - 1)) < 0.01


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"ground": (1.0, 1.0)}, "three RMS"),
        ({"noise": -0.1}, "noise"),
        ({"damping": 1.5}, "damping ratios"),
        ({"loads": {"X9.uz": 1.0}}, "no node 'X9'"),
        ({"duration": 0.0}, "duration"),
    ],
)
def test_bad_requests_are_named(column, kwargs, message):
    args = {"duration": 10.0, **kwargs}
    duration = args.pop("duration")
    with pytest.raises(ParameterError, match=message):
        simulate_ambient(column, ["C6.ux"], duration, 0.01, **args)


def test_unknown_sensor_is_named(column):
    with pytest.raises(ParameterError, match="'C6.qq' does not name a DOF"):
        simulate_ambient(column, ["C6.qq"], 10.0, 0.01)
