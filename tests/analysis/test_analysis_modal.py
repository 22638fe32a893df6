"""Modal analysis against Euler-Bernoulli and St-Venant closed forms; participation; labels; MAC."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from kernel_models import RECT, STEEL, cantilever_model, deck_model

import bearingfw.analysis.modal as modal_module
from bearingfw.analysis import ConvergenceError, automac, eigen, gravity, mac, solve_modal
from bearingfw.model import Connector, FrameElement, Model, ModelError, NodalMass, Node, RigidLink, build_system

L = 10.0
# beta_n L of a clamped-free beam (roots of cos(x) cosh(x) = -1)
CANTILEVER_BETA_L = (1.8751040687119611, 4.6940911329741745, 7.8547574382376126)


def bending(beta_l, inertia):
    return beta_l**2 * np.sqrt(STEEL.E * inertia / (STEEL.density * RECT.A * L**4)) / (2 * np.pi)


def torsion(n, clamped_free):
    c = np.sqrt(STEEL.shear_modulus * RECT.J / (STEEL.density * RECT.Ip))
    k = (2 * n - 1) * np.pi / (2 * L) if clamped_free else n * np.pi / L
    return k * c / (2 * np.pi)


def first(result, label, count):
    return np.array([result.frequencies[result.find(label, k)] for k in range(1, count + 1)])


@pytest.mark.parametrize("mass", ["consistent", "lumped"])
def test_cantilever_frequencies_within_one_percent(mass):
    res = solve_modal(cantilever_model(n=20, L=L, mass=mass), 10)
    vertical, lateral = first(res, "vertical", 3), first(res, "lateral", 3)
    np.testing.assert_allclose(vertical, [bending(b, RECT.Iy) for b in CANTILEVER_BETA_L], rtol=0.01)
    np.testing.assert_allclose(lateral, [bending(b, RECT.Iz) for b in CANTILEVER_BETA_L], rtol=0.01)
    assert res.frequencies[res.find("torsional")] == pytest.approx(torsion(1, True), rel=0.01)


@pytest.mark.parametrize("mass", ["consistent", "lumped"])
def test_simply_supported_frequencies_within_one_percent(mass):
    res = solve_modal(cantilever_model(n=20, L=L, mass=mass, support="simple"), 10)
    vertical, lateral = first(res, "vertical", 3), first(res, "lateral", 3)
    np.testing.assert_allclose(vertical, [bending(n * np.pi, RECT.Iy) for n in (1, 2, 3)], rtol=0.01)
    np.testing.assert_allclose(lateral, [bending(n * np.pi, RECT.Iz) for n in (1, 2, 3)], rtol=0.01)
    assert res.frequencies[res.find("torsional")] == pytest.approx(torsion(1, False), rel=0.01)


def test_consistent_mass_converges_much_tighter():
    """With 20 consistent elements the error of the 3rd mode is far below 1 % (~1e-4)."""
    res = solve_modal(cantilever_model(n=20, L=L), 10)
    assert first(res, "vertical", 3)[2] == pytest.approx(bending(CANTILEVER_BETA_L[2], RECT.Iy), rel=1e-3)


def test_dense_and_sparse_eigen_solvers_agree():
    system = build_system(cantilever_model(n=20, L=L))
    dense, sparse = solve_modal(system, 8, method="dense"), solve_modal(system, 8, method="sparse")
    np.testing.assert_allclose(dense.frequencies, sparse.frequencies, rtol=1e-9)
    np.testing.assert_allclose(np.diag(mac(dense.shapes, sparse.shapes)), 1.0, atol=1e-9)
    # shapes are mass-normalised and M-orthogonal
    gram = sparse.shapes.T @ system.M @ sparse.shapes
    np.testing.assert_allclose(gram, np.eye(8), atol=1e-9)


def free_free_beam(n=4, mass="consistent"):
    nodes = [Node(f"N{k}", 2.0 * k, 0.3 * k, 0.1 * k * k) for k in range(n + 1)]  # a bent member
    elements = [FrameElement(f"E{k}", f"N{k}", f"N{k + 1}", RECT, STEEL, mass=mass) for k in range(n)]
    return Model(nodes, elements, masses=[NodalMass("N2", 500.0, ixx=80.0, iyy=40.0, izz=60.0)])


def test_effective_masses_of_all_modes_sum_to_the_total_mass_free_free():
    system = build_system(free_free_beam())
    res = solve_modal(system, system.n_free)  # every mode, the six rigid-body ones included
    assert np.sum(res.frequencies < 1e-3) == 6
    for d in ("x", "y", "z", "rx", "ry", "rz"):
        assert res.effective_mass[d].sum() == pytest.approx(res.total_mass[d], rel=1e-9)
    length = sum(
        np.linalg.norm(np.subtract(system.model.node(e.j).xyz, system.model.node(e.i).xyz))
        for e in system.model.elements
    )
    assert res.total_mass["z"] == pytest.approx(STEEL.density * RECT.A * length + 500.0, rel=1e-12)


def test_effective_masses_sum_to_the_mass_that_can_move():
    """Lumped mass, clamped at N0: the modes carry everything but the half element at the clamp."""
    n = 4
    system = build_system(cantilever_model(n=n, L=L, mass="lumped"))
    massive = int(np.count_nonzero(system.M_free.diagonal()))
    res = solve_modal(system, massive)
    moving = STEEL.density * RECT.A * L * (1 - 1 / (2 * n))
    for d in ("x", "y", "z"):
        assert res.effective_mass[d].sum() == pytest.approx(moving, rel=1e-9)
        assert res.movable_mass[d] == pytest.approx(moving, rel=1e-9)
        assert res.total_mass[d] == pytest.approx(STEEL.density * RECT.A * L, rel=1e-12)  # all of it
        assert res.mass_ratios[d].sum() == pytest.approx(1.0, rel=1e-9)


@pytest.mark.parametrize("mass", ["consistent", "lumped"])
def test_movable_mass_is_the_sum_over_all_modes_with_supports_and_an_offset_mass(mass):
    """A clamped member with a rigidly offset nodal mass: the ratios of all modes sum to 1."""
    base = cantilever_model(n=4, L=6.0, mass=mass)
    model = Model(
        [*base.nodes, Node("off", 6.0, 1.5, -0.8)],
        base.elements,
        rigid_links=[RigidLink("offset", "N4", "off")],
        supports=base.supports,
        masses=[NodalMass("off", 1000.0, ixx=50.0)],
    )
    system = build_system(model)
    res = solve_modal(system, int(np.linalg.matrix_rank(system.M_free.toarray())), method="dense")
    for d in ("x", "y", "z", "rx", "ry", "rz"):
        assert res.effective_mass[d].sum() == pytest.approx(res.movable_mass[d], rel=1e-9)
        assert res.mass_ratios[d].sum() == pytest.approx(1.0, rel=1e-9)
    assert res.movable_mass["z"] < res.total_mass["z"]


def test_energy_shares_partition_the_kinetic_energy_and_labels_follow_the_shape():
    res = solve_modal(cantilever_model(n=10, L=L), 8)
    sys = res.system
    # the kinetic energy p = phi * (M phi) of a mass-normalised mode sums to 1, and on this
    # member along the deck axis (no mirror nodes, no antisymmetric uz) each label's share is
    # the energy of its own components
    p = res.shapes * (sys.M @ res.shapes)
    np.testing.assert_allclose(p.sum(axis=0), 1.0, rtol=1e-9)
    energy = {c: p[sys.dofmap.component_dofs(c)].sum(axis=0) for c in ("ux", "uy", "uz", "rx", "ry", "rz")}
    np.testing.assert_allclose(res.shares["longitudinal"], energy["ux"], atol=1e-12)
    np.testing.assert_allclose(res.shares["lateral"], energy["uy"] + energy["rz"], atol=1e-12)
    np.testing.assert_allclose(res.shares["vertical"], energy["uz"] + energy["ry"], atol=1e-12)
    np.testing.assert_allclose(res.shares["torsional"], energy["rx"], atol=1e-12)
    assert max(max(v) for v in res.shares.values()) > 0.99  # the modes are pure
    for m, label in enumerate(res.labels):
        phi = res.shapes[:, m]
        parts = {c: np.linalg.norm(phi[sys.dofmap.component_dofs(c)]) for c in ("ux", "uy", "uz", "rx")}
        dominant = {"ux": "longitudinal", "uy": "lateral", "uz": "vertical", "rx": "torsional"}
        # compare rotations at the scale of the section (rx * radius of gyration)
        parts["rx"] *= np.sqrt(RECT.Ip / RECT.A)
        assert dominant[max(parts, key=parts.get)] == label


def test_twin_girder_torsion_is_labelled_torsional():
    """The deck's twisting mode: the two girders move vertically in opposition."""
    res = solve_modal(deck_model("linear-spring", {"k": 4e8}), 12)
    sys = res.system
    t = res.find("torsional")
    v = res.find("vertical")
    wa = res.shapes[sys.dofmap.dofs([f"GA{k}" for k in range(9)], ["uz"]), :]
    wb = res.shapes[sys.dofmap.dofs([f"GB{k}" for k in range(9)], ["uz"]), :]
    assert np.dot(wa[:, t], wb[:, t]) < -0.9 * np.linalg.norm(wa[:, t]) * np.linalg.norm(wb[:, t])
    assert np.dot(wa[:, v], wb[:, v]) > 0.9 * np.linalg.norm(wa[:, v]) * np.linalg.norm(wb[:, v])


@settings(max_examples=25, deadline=None)
@given(angle=st.floats(0.0, 2 * np.pi))
def test_isotropic_planar_connector_does_not_depend_on_its_frame_orientation(angle):
    """Rotating a PLANAR connector's x axis about its z axis leaves an isotropic law unchanged."""
    base = deck_model("linear-spring", {"k": 4e8}, per_span=2)
    x_axis = (np.cos(angle), np.sin(angle), 0.0)
    rotated = Model(
        base.nodes,
        base.elements,
        [
            Connector(
                c.name,
                c.node_i,
                c.node_j,
                c.kind,
                c.law,
                c.params,
                c.vertical_stiffness,
                c.guided,
                x_axis if c.kind.value == "planar" else c.x_axis,
            )
            for c in base.connectors
        ],
        base.rigid_links,
        base.supports,
        base.masses,
    )
    a, b = gravity(base), gravity(rotated)
    np.testing.assert_allclose(a.normal_forces, b.normal_forces, rtol=1e-9)
    np.testing.assert_allclose(
        solve_modal(base, 4, preload=a).frequencies, solve_modal(rotated, 4, preload=b).frequencies, rtol=1e-9
    )


def test_eigen_rejects_infinite_eigenvalues_in_both_solvers():
    """M = V V^T of rank 3 on 60 DOFs, every diagonal term non-zero: 3 finite eigenvalues.

    The count of DOFs with mass (60) does not see the 57 infinite eigenvalues; both solvers
    must (the sparse one used to return a spurious ~1e10).
    """
    V = np.random.default_rng(0).uniform(0.5, 1.5, (60, 3))
    K = sp.diags(np.arange(1.0, 61.0)).tocsr()
    M = sp.csr_matrix(V @ V.T)
    lowest = eigen(K, M, 3, method="dense")[0]
    for method in ("dense", "sparse"):
        np.testing.assert_allclose(eigen(K, M, 3, method=method)[0], lowest, rtol=1e-9)
        with pytest.raises(ModelError, match="has only 3 with mass"):
            eigen(K, M, 4, method=method)
    with pytest.raises(ValueError, match="shift must be negative"):  # ModelError is a ValueError
        eigen(K, M, 1, shift=1.0)


def test_a_preload_that_does_not_converge_falls_back_with_a_warning(monkeypatch):
    def no_convergence(*args, **kwargs):
        raise ConvergenceError("solve_static: no equilibrium after 50 Newton iterations")

    monkeypatch.setattr(modal_module, "gravity", no_convergence)
    with pytest.warns(UserWarning, match="gravity preload failed \\(ConvergenceError"):
        res = solve_modal(deck_model("regularized-coulomb", {"k": 4e8, "mu": 0.04}, per_span=2), 3)
    assert not np.any(res.normal_forces)


def test_the_automatic_preload_sets_the_bearings_after_the_dead_load_by_default(monkeypatch):
    seen = []

    def spy(system, **kwargs):
        seen.append(kwargs.get("bearings"))
        return gravity(system, **kwargs)

    monkeypatch.setattr(modal_module, "gravity", spy)
    model = deck_model("regularized-coulomb", {"k": 4e8, "mu": 0.04}, per_span=2)
    solve_modal(model, 2)
    solve_modal(model, 2, bearings="active")
    assert seen == ["set-after-dead-load", "active"]
    with pytest.raises(ModelError, match="parameter 'bearings'"):  # an error, not a warning
        solve_modal(model, 2, bearings="frozen")


# --- MAC ------------------------------------------------------------------------------------
shape_sets = (
    st.integers(2, 6)
    .flatmap(lambda m: arrays(np.float64, (12, m), elements=st.floats(-1e3, 1e3, allow_subnormal=False)))
    .filter(lambda a: np.all(np.linalg.norm(a, axis=0) > 1e-3))
)


@settings(max_examples=100, deadline=None)
@given(phi=shape_sets, data=st.data())
def test_mac_is_one_on_the_diagonal_and_scale_and_sign_invariant(phi, data):
    m = phi.shape[1]
    scales = np.array(data.draw(st.lists(st.floats(1e-3, 1e3), min_size=m, max_size=m)))
    signs = np.array(data.draw(st.lists(st.sampled_from([-1.0, 1.0]), min_size=m, max_size=m)))
    auto = automac(phi)
    np.testing.assert_allclose(np.diag(auto), 1.0, rtol=1e-12)
    assert np.all((auto >= 0) & (auto <= 1 + 1e-12))
    np.testing.assert_allclose(mac(phi * scales * signs, phi), auto, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(mac(phi, -phi * scales), auto, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(mac(phi[:, ::-1], phi), auto[::-1], rtol=1e-9, atol=1e-12)


def test_mac_of_computed_modes_at_chosen_dofs():
    res = solve_modal(cantilever_model(n=20, L=L), 6)
    sensors = res.system.dofmap.dofs([f"N{k}" for k in (5, 10, 15, 20)], ["uy", "uz"])
    auto = automac(res.shapes, sensors)
    np.testing.assert_allclose(np.diag(auto), 1.0, rtol=1e-12)
    # vertical and lateral modes are orthogonal at these DOFs, whatever the sensors
    v, lat = res.find("vertical"), res.find("lateral")
    assert auto[v, lat] < 1e-12
    with pytest.raises(ValueError, match="zero"):
        mac(res.shapes, res.shapes, res.system.dofmap.dofs(["N0"], ["uz"]))
