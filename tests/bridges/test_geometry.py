"""The reference bridge as built: members, bearings, offsets, response elements, parameters."""

from __future__ import annotations

import attrs
import pytest

from bearingfw.bridges import (
    ABUTMENT_AXES,
    BEARINGS,
    PILLAR_AXES,
    RESPONSE_ELEMENTS,
    BridgeParameters,
    bearing_offset,
    grid,
    reference_bridge,
)
from bearingfw.bridges.paper import BEARING_CAPACITY, HANGERS, LENGTH, PILLAR_STIFFNESS, TENDON_AREA
from bearingfw.bridges.sections import girder_geometry
from bearingfw.model import ConnectorKind, FrameElement, Material, ModelError, TrussElement, build_system
from bearingfw.parameters import ParameterError


@pytest.fixture(scope="module")
def model():
    return reference_bridge("M0")


def test_overall_layout(model, params):
    assert params.length == pytest.approx(LENGTH)
    assert max(params.spans) == params.spans[2]  # the arch span is the longest, in the middle
    hangers = [e for e in model.elements if isinstance(e, TrussElement) and e.name.startswith("H")]
    assert len(hangers) == HANGERS
    xyz = model.coordinates
    for h in hangers:  # vertical, from the girder up to the arch, inside the arch span
        i, j = xyz[model.node_index(h.i)], xyz[model.node_index(h.j)]
        assert i[:2] == pytest.approx(j[:2]) and j[2] > i[2]
        assert params.axis_positions[2] < i[0] < params.axis_positions[3]
    system = build_system(model)
    assert system.n_dof < 3000  # small enough for many time histories


def test_bearing_layout_follows_the_paper(model):
    expected = {4: {"A": ("join", None), "B": ("axial", "y")}}
    for name, spec in BEARINGS.items():
        c = model.connector(name)
        kind, guided = expected.get(spec.axis, {"A": ("axial", "x"), "B": ("planar", None)})[spec.side]
        assert (c.kind.value, c.guided) == (kind, guided), name
        assert spec.capacity == BEARING_CAPACITY[spec.axis]
    assert sorted(BEARINGS) == sorted(f"{a}{s}" for a in range(1, 7) for s in "AB")


def test_bearings_sit_on_pillars_or_abutments_at_the_end_of_rigid_offsets(model, params):
    supported = {s.node: s.dofs for s in model.supports}
    offset = bearing_offset(params)
    assert offset == pytest.approx(girder_geometry(params).centroid + params.bearing_height)
    links = {link.slave: link.master for link in model.rigid_links}
    xyz = model.coordinates
    for name, spec in BEARINGS.items():
        c = model.connector(name)
        girder = links[c.node_j]
        assert girder.startswith(f"G{spec.side}")
        drop = xyz[model.node_index(girder)] - xyz[model.node_index(c.node_j)]
        assert drop == pytest.approx([0.0, 0.0, offset])
        if spec.axis in ABUTMENT_AXES:
            assert supported[c.node_i] == ("ux", "uy", "uz", "rx", "ry", "rz")
        else:
            assert spec.axis in PILLAR_AXES and c.node_i == f"P{name}.{params.pillar_elements}"
            assert supported[f"P{name}.0"] == ("ux", "uy", "uz", "rx", "ry", "rz")


def test_pillars_have_the_papers_bending_stiffness(model, params):
    pillar = model.element("P2A.1")
    height = params.pillar_height
    stiffness = 3 * pillar.material.E * pillar.section.Iy / height**3  # eq. 7: a cantilever under a pinned bearing
    assert stiffness == pytest.approx(PILLAR_STIFFNESS, rel=1e-12)
    assert pillar.section.Iy == pytest.approx(1.4**4 / 12)
    assert 30e9 < pillar.material.E < 33e9  # close to C30/37's E_cm


def test_girders_get_eq1(model, params):
    girder = model.element("S1")
    area = girder_geometry(params).area
    expected = (params.girder_concrete_modulus * area + params.tendon_modulus * TENDON_AREA) / (area + TENDON_AREA)
    assert girder.material.E == pytest.approx(expected)
    assert girder.material.E == pytest.approx(Material.composite_modulus(35e9, area, 195e9, 150e-4))


def test_response_elements(model, params):
    g = grid(params)
    x = g.x
    for name in RESPONSE_ELEMENTS:
        e = model.element(name)
        assert isinstance(e, FrameElement) and e.i.startswith("G") and e.j.startswith("G")
        assert {p.name for p in e.section.points} >= {"bottom", "top", "bottom-left", "bottom-right"}
    mid = (params.axis_positions[2] + params.axis_positions[3]) / 2
    assert [model.element(n).i for n in ("S1", "S2")] == [f"GA{g.middle}", f"GB{g.middle}"]
    assert x[g.middle] == pytest.approx(mid)
    for axis in PILLAR_AXES:
        for side in "AB":
            e = model.element(f"{axis}{side}")
            # end i over the bearing of that axis and girder
            assert e.i == model.rigid_link(f"L{axis}{side}").master


def test_fixed_and_sliding_presets_differ_only_in_the_bearings():
    m0, fixed = reference_bridge("M0"), reference_bridge("fixed")
    assert all(c.kind is ConnectorKind.JOIN for c in fixed.connectors)
    assert [e.name for e in m0.elements] == [e.name for e in fixed.elements]


@pytest.mark.parametrize(
    "change, message",
    [
        ({"spans": (20.0, 30.0, 60.0)}, "'spans'"),
        ({"element_length": 3.0}, "element_length"),
        ({"girder_depth": 0.1}, "'girder_depth'"),
        ({"arch_springings": "pinned"}, "'arch_springings'"),
        ({"bracing_struts": 2.5}, "'bracing_struts'"),
    ],
)
def test_parameter_errors_name_the_field(change, message):
    with pytest.raises((ParameterError, ModelError), match=message):
        reference_bridge("M0", params=attrs.evolve(BridgeParameters(), **change))


def test_every_parameter_is_documented():
    for field in attrs.fields(BridgeParameters):
        assert field.metadata.get("doc"), field.name
