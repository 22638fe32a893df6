"""Bad input is rejected with an error that names the object and the field."""

from __future__ import annotations

import numpy as np
import pytest

from bearingfw import ParameterError
from bearingfw.model import (
    Connector,
    DofMap,
    FrameElement,
    Material,
    Model,
    ModelError,
    NodalMass,
    Node,
    RigidLink,
    Section,
    Support,
    TrussElement,
    build_system,
)

STEEL = Material("steel", 210e9, density=7850.0)
SEC = Section("s", A=0.01, Iy=1e-4, Iz=2e-4, J=5e-5)


def two_nodes(z=0.0):
    return [Node("a", 0, 0, 0), Node("b", 0, 0, z)]


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: Section("deck", A=-1.0, Iy=1, Iz=1, J=1), r"deck.*'A' = -1.0 is outside the allowed range A > 0"),
        (lambda: Section("deck", A=1.0, Iy=0.0, Iz=1, J=1), r"'Iy' = 0.0 .* Iy > 0"),
        (lambda: Section("deck", A=1.0, Iy=1, Iz=1, J=1, Avy=-2.0), r"'Avy' = -2.0"),
        (lambda: Material("c", E=-3e10), r"Material 'c': parameter 'E' = -30000000000.0 is outside the allowed range E > 0"),
        (lambda: Material("c", E=3e10, nu=0.7), r"'nu' = 0.7"),
        (lambda: Material("c", E=3e10, density="heavy"), r"'density' must be a real number"),
        (lambda: Node("n", 0.0, float("nan"), 0.0), r"'y' = nan"),
        (lambda: Node("", 0, 0, 0), r"field 'name' must be a non-empty string"),
        (lambda: TrussElement("h1", "a", "b", area=0.0, material=STEEL), r"'area' = 0.0"),
        (lambda: FrameElement("e", "a", "a", SEC, STEEL), r"fields 'i' and 'j' name the same node"),
        (lambda: FrameElement("e", "a", "b", SEC, "steel"), r"field 'material' must be a Material"),
        (lambda: FrameElement("e", "a", "b", SEC, STEEL, mass="diagonal"), r"parameter 'mass' must be one of"),
        (lambda: FrameElement("e", "a", "b", SEC, STEEL, shear_deformation=True), r"needs the shear areas"),
        (lambda: FrameElement("e", "a", "b", SEC, STEEL, orientation=(0, 0, 0)), r"'orientation' must be a non-zero"),
        (lambda: Support("a", ("ux", "wz")), r"field 'dofs'"),
        (lambda: NodalMass("a", -5.0), r"'mass' = -5.0"),
        (lambda: Connector("3B", "a", "b", "hinge"), r"field 'kind'"),
        (
            lambda: Connector("3B", "a", "b", "planar", law="linear-spring", law_params={"k": 1e8}),
            r"connector '3B': field 'vertical_stiffness' is required",
        ),
        (lambda: Connector("3B", "a", "b", "planar", vertical_stiffness=1e9), r"connector '3B': field 'law' must name"),
        (lambda: Connector("3B", "a", "b", "join", law="fixed"), r"connector '3B': field 'law' must be None"),
        (lambda: Connector("3B", "a", "b", "axial", law="x", vertical_stiffness=1e9, guided="z"), r"parameter 'guided'"),
        (lambda: Connector("3B", "a", "b", "axial", law="x", vertical_stiffness=-1.0), r"'vertical_stiffness' = -1.0"),
        (lambda: Connector("3B", "a", "b", "join", x_axis=(0, 0, 2)), r"'x_axis' and 'z_axis' are parallel"),
        (
            lambda: Connector("3B", "a", "b", "planar", law="x", law_params={"dims": 1}, vertical_stiffness=1.0),
            r"'law_params' must not set 'dims'",
        ),
        (lambda: RigidLink("r", "a", "a"), r"RigidLink 'r': fields 'master' and 'slave'"),
        (
            lambda: Connector("3B", "a", "b", "join", z_axis=(0, 0, -1)),
            r"connector '3B': field 'z_axis' \(0.0, 0.0, -1.0\) must point up",
        ),
        (
            lambda: Connector("3B", "a", "b", "planar", law="x", vertical_stiffness=1e9, z_axis=(1, 0, -1e-3)),
            r"connector '3B': field 'z_axis' .* must point up",
        ),
        (lambda: Connector("3B", "a", "b", "join", x_axis=(0, 0, 1), z_axis=(1, 0, 0)), r"field 'z_axis' .* point up"),
        (
            lambda: Connector("3B", "a", "b", "planar", law="x", vertical_stiffness=1e9, guided="x"),
            r"connector '3B': field 'guided' applies to AXIAL connectors only",
        ),
        (lambda: Connector("3B", "a", "b", "join", guided="y"), r"connector '3B': field 'guided' applies to AXIAL"),
    ],
)
def test_bad_fields_are_named(make, message):
    with pytest.raises(ParameterError, match=message):
        make()


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (
            dict(connectors=[Connector("3B", "a", "ghost", "join")]),
            r"connector '3B': field 'node_j' names unknown node 'ghost'",
        ),
        (
            dict(elements=[FrameElement("e", "a", "ghost", SEC, STEEL)]),
            r"FrameElement 'e': field 'j' names unknown node",
        ),
        (dict(rigid_links=[RigidLink("r", "ghost", "a")]), r"RigidLink 'r': field 'master' names unknown node"),
        (dict(supports=[Support("ghost")]), r"names unknown node 'ghost'"),
        (dict(masses=[NodalMass("ghost", 1.0)]), r"names unknown node 'ghost'"),
        (dict(supports=[Support("a"), Support("a", ("rz",))]), r"two supports at node 'a'"),
        (dict(elements=[FrameElement("e", "a", "b", SEC, STEEL)] * 2), r"field 'elements' has two entries named 'e'"),
        (dict(connectors=["not a connector"]), r"field 'connectors' holds"),
    ],
)
def test_bad_references_are_named(kwargs, message):
    with pytest.raises(ModelError, match=message):
        Model(two_nodes(1.0), **kwargs)


def test_connector_nodes_must_coincide_and_elements_have_length():
    with pytest.raises(ModelError, match=r"connector 'c': nodes 'a' and 'b' are 0.5 m apart"):
        Model(two_nodes(0.5), connectors=[Connector("c", "a", "b", "join")])
    with pytest.raises(ModelError, match=r"zero length"):
        Model(two_nodes(0.0), elements=[FrameElement("e", "a", "b", SEC, STEEL)])
    with pytest.raises(ModelError, match=r"duplicate|two entries named 'a'"):
        Model([Node("a", 0, 0, 0), Node("a", 1, 0, 0)])


def test_axial_connectors_are_guided_along_x_by_default_and_tilted_frames_are_accepted():
    axial = Connector("1A", "a", "b", "axial", law="x", vertical_stiffness=1e9)
    assert axial.guided == "x" and axial.law_directions == (0,) and axial.tied_directions == (1,)
    assert Connector("1B", "a", "b", "planar", law="x", vertical_stiffness=1e9).guided is None
    tilted = Connector("1C", "a", "b", "planar", law="x", vertical_stiffness=1e9, z_axis=(0.05, 0, 1))
    assert tilted.rotation[2, 2] > 0.99


def test_a_member_with_an_orientation_along_its_axis_is_named():
    model = Model(
        [Node("a", 0, 0, 0), Node("b", 1, 0, 0)],
        [FrameElement("beam7", "a", "b", SEC, STEEL, orientation=(2, 0, 0))],
        supports=[Support("a")],
    )
    with pytest.raises(ModelError, match=r"FrameElement 'beam7': field 'orientation' \(2.0, 0.0, 0.0\) is parallel"):
        build_system(model)


def test_node_names_are_indexed_once_by_the_dof_map():
    model = Model(two_nodes(1.0))
    assert model.dofmap.node_names == ("a", "b") and model.node_index("b") == 1
    np.testing.assert_array_equal(model.dofmap.node_dofs(["b", "a"]), [np.arange(6, 12), np.arange(6)])
    with pytest.raises(ModelError, match=r"Model: no node named 'c'"):
        model.node("c")
    with pytest.raises(ModelError, match=r"DofMap: field 'node_names' repeats 'a'"):
        DofMap(("a", "b", "a"))


def test_unknown_law_and_bad_law_parameter_name_the_connector_and_field():
    nodes = two_nodes(0.0)
    base = dict(vertical_stiffness=1e9)
    model = Model(nodes, connectors=[Connector("3B", "a", "b", "planar", law="teflon-magic", **base)])
    with pytest.raises(
        ModelError, match=r"connector '3B': field 'law': unknown bearing law 'teflon-magic'; known laws:"
    ):
        build_system(model)
    model = Model(
        nodes, connectors=[Connector("3B", "a", "b", "planar", law="linear-spring", law_params={"k": -1.0}, **base)]
    )
    with pytest.raises(ModelError, match=r"connector '3B': field 'law_params': .*'k' = -1.0"):
        build_system(model)
    model = Model(
        nodes, connectors=[Connector("3B", "a", "b", "planar", law="linear-spring", law_params={"kk": 1.0}, **base)]
    )
    with pytest.raises(ModelError, match=r"field 'law_params': .*unknown parameter\(s\) 'kk'"):
        build_system(model)


def test_lookups_and_law_swapping():
    nodes = [Node("p", 0, 0, 0), Node("s", 0, 0, 0), Node("q", 5, 0, 0), Node("t", 5, 0, 0)]
    cons = [
        Connector("1A", "p", "s", "join"),
        Connector("1B", "q", "t", "planar", law="frictionless", vertical_stiffness=1e9),
    ]
    model = Model(nodes, connectors=cons)
    assert model.connector("1B").kind.value == "planar" and model.node_index("q") == 2
    with pytest.raises(ModelError, match=r"no connector named '9Z'"):
        model.connector("9Z")
    spring = model.with_law("linear-spring", {"k": 4e8})
    assert spring.connector("1B").law == "linear-spring" and spring.connector("1B").params == {"k": 4e8}
    assert spring.connector("1A").law is None  # JOIN untouched
    assert model.connector("1B").law == "frictionless"  # the original is unchanged
    with pytest.raises(ModelError, match="must be None for a JOIN"):
        model.with_law("linear-spring", {"k": 1.0}, connectors=["1A"])
