"""Recording a run of compiled steps at once (issue 16): the recorders read the run's arrays side by
side (:class:`bearingfw.analysis.recorders.Samples`), in the same chunks as when the steps come one
by one, so that a result never depends on how its steps were taken; a recorder that takes one
snapshot at a time still sees every instant; the ground motion of a run of instants is that of each."""

from __future__ import annotations

import numpy as np
import pytest
from kernel_models import band_limited_noise, deck_model

from bearingfw.analysis import (
    ConnectorResponse,
    ElementForces,
    NodalResponse,
    Rayleigh,
    TransientSettings,
    gravity,
    hht,
    solve_transient,
)
from bearingfw.analysis.excitation import build_excitation
from bearingfw.analysis.recorders import Context, Samples, Snapshot
from bearingfw.model import build_system

DT = 0.005
COULOMB = {"k": 4e8, "mu": 0.04}


@pytest.fixture(scope="module")
def deck():
    system = build_system(deck_model("regularized-coulomb", COULOMB))
    pre = gravity(system)
    ag = band_limited_noise(101, DT, seed=11, amplitude=[6.0, 4.0, 3.0])
    return system, pre, ag


def _snapshots(system, pre, exc, count: int, seed: int) -> list[Snapshot]:
    """Instants with random kinematics and law forces (the recorders' maps are linear in them)."""
    rng = np.random.default_rng(seed)
    n, m = system.n_free, pre.law_forces.size
    out = []
    for k in range(count):
        t = DT * (k + 1)
        ag, vg = exc.ground(t)
        out.append(Snapshot(t, *(rng.normal(size=n) * 1e-3 for _ in range(3)), pre.law_forces + rng.normal(size=m),
                            tuple(pre.law_states), ag, vg, None, rng.normal(size=m) * 1e-3, rng.normal(size=n)))
    return out


def _stacked(snapshots) -> Samples:
    """The snapshots as one run's arrays (as a run of compiled steps hands them over)."""
    parts = Samples.of(snapshots)
    return Samples(list(parts.law_states), **{f: getattr(parts, f) for f in Samples.ARRAYS + Samples.OPTIONAL})


def _recorded(system, pre, exc, feed) -> dict:
    ctx = Context(system, pre, exc, 0.21, 0.00208)
    specs = [ConnectorResponse(name="bearings"), ElementForces([e.name for e in system.model.elements][:3]),
             NodalResponse([system.model.nodes[-1].name], "acceleration", total=True)]
    out = {}
    for spec in specs:
        probe = spec.bind(ctx)
        feed(probe)
        data, _ = probe.finish()
        out.update(data)
    return out


def test_a_probe_evaluates_the_same_chunks_however_the_instants_come(deck):
    """One by one, in runs of any length, or mixed: the recorded arrays are equal bit for bit (a dense
    product's rounding can depend on how many instants it takes at once, so the chunks must not)."""
    system, pre, ag = deck
    exc = build_excitation(system, ag, DT, None, preload=pre)
    snaps = _snapshots(system, pre, exc, 200, seed=1)

    def one_by_one(probe):
        for s in snaps:
            probe.sample(s)

    def in_runs(probe):
        start = 0
        for size in (1, 3, 70, 2, 100, 5, 19):
            probe.sample_many(_stacked(snaps[start:start + size]))
            start += size
        assert start == len(snaps)

    def mixed(probe):
        probe.sample(snaps[0])
        probe.sample_many(_stacked(snaps[1:90]))
        for s in snaps[90:95]:
            probe.sample(s)
        probe.sample_many(_stacked(snaps[95:]))

    reference = _recorded(system, pre, exc, one_by_one)
    assert reference["bearings.force"].shape[0] == 200 and np.abs(reference["bearings.force"]).max() > 0
    for feed in (in_runs, mixed):
        other = _recorded(system, pre, exc, feed)
        assert other.keys() == reference.keys()
        for key, value in reference.items():
            assert np.array_equal(other[key], value, equal_nan=True), (feed.__name__, key)


def test_samples_taken_joined_and_split_are_the_instants_they_hold(deck):
    system, pre, ag = deck
    exc = build_excitation(system, ag, DT, None, preload=pre)
    snaps = _snapshots(system, pre, exc, 12, seed=2)
    run = _stacked(snaps[4:])
    joined = Samples.of([*snaps[:4], run])
    assert len(joined) == 12
    for field in Samples.ARRAYS + ("d", "a_equilibrium"):
        assert np.array_equal(getattr(joined, field), np.array([getattr(s, field) for s in snaps])), field
    assert joined.nodal is None  # the instants have no nodal loads
    some = run.take(np.array([0, 3, 7]))
    assert np.array_equal(some.x, np.array([snaps[4].x, snaps[7].x, snaps[11].x]))
    assert [s.t for s in some.each()] == [snaps[4].t, snaps[7].t, snaps[11].t]
    back = run.snapshot(2)
    assert back.t == snaps[6].t and np.array_equal(back.f, snaps[6].f) and back.law_states is snaps[6].law_states
    with pytest.raises(TypeError, match="give every one"):
        Samples([], t=np.zeros(0))


def test_law_states_are_read_only_where_a_probe_reads_them():
    """A run's law states are unpacked per step on demand: joining and taking instants reads none."""
    reads = []

    class Counting:
        def __len__(self):
            return 5

        def __getitem__(self, j):
            j = range(5)[j]
            reads.append(j)
            return ("state", j)

    arrays = {f: np.arange(5.0) for f in Samples.ARRAYS} | dict.fromkeys(Samples.OPTIONAL)
    run = Samples(Counting(), **arrays)
    picked = Samples.of([run.take(slice(1, 4)), run.take(np.array([4]))])
    assert len(picked) == 4 and reads == []
    assert picked.law_states[1] == ("state", 2) and reads == [2]
    assert list(picked.law_states) == [("state", 1), ("state", 2), ("state", 3), ("state", 4)]


def test_a_recorder_that_takes_one_snapshot_at_a_time_sees_every_instant_of_a_compiled_run(deck, monkeypatch):
    system, pre, ag = deck

    class EveryThird:
        label, every = "third", 3

        def bind(self, ctx):
            return _Collect(self.label, self.every)

    class _Collect:
        def __init__(self, label, every):
            self.label, self.every, self.times, self.x = label, every, [], []

        def sample(self, s):
            self.times.append(s.t)
            self.x.append(s.x.copy())

        def finish(self):
            return {self.label: np.array(self.x), f"{self.label}.time": np.array(self.times)}, {}

    results = []
    for compiled in (False, True):
        monkeypatch.setattr(hht, "COMPILED_STEPS", compiled)
        step, calls = hht.step, []
        monkeypatch.setattr(hht, "step", lambda *a, **k: calls.append(1) or step(*a, **k))
        res = solve_transient(system, ag, DT, preload=pre, damping=Rayleigh(0.21, 0.00208),
                              settings=TransientSettings(alpha=-0.05), recorders=[EveryThird()])
        results.append((res, len(calls)))
    (python, python_steps), (compiled, compiled_steps) = results
    assert python_steps == 100 and compiled_steps == 0
    assert np.array_equal(compiled["third.time"], python["third.time"]) and compiled["third.time"].size == 34
    assert np.array_equal(compiled["third"], python["third"])


@pytest.mark.parametrize("steps", [101, 2])
def test_the_ground_motion_of_a_run_of_instants_is_that_of_each(deck, steps):
    system, pre, ag = deck
    exc = build_excitation(system, ag[:steps], 0.01, None, preload=pre)
    times = [-0.01, 0.0, 0.0025, 0.005, 0.01, 0.0175, 0.2, 0.3999, 0.4, 0.45, 1.0, 1.5]
    acc, vel = exc.grounds(times)
    assert acc.shape == vel.shape == (len(times), 3)
    for t, a, v in zip(times, acc, vel, strict=True):
        a1, v1 = exc.ground(t)
        assert np.array_equal(a, a1) and np.array_equal(v, v1), t
    assert np.abs(vel).max() > 0


def test_the_section_force_map_is_read_once_per_system(deck, monkeypatch):
    """The cells of an experiment share a system: the map from displacements to section forces is
    read off the kernel (one call per DOF) once for it, not once per run; a run on another system
    (another model) reads its own."""
    from bearingfw.analysis import recorders

    _, _, ag = deck
    system = build_system(deck_model("regularized-coulomb", COULOMB))
    pre = gravity(system)
    reads = []
    real = recorders._read_force_map
    monkeypatch.setattr(recorders, "_read_force_map", lambda sys, names: reads.append(names) or real(sys, names))
    names = [e.name for e in system.model.elements][:3]
    runs = [solve_transient(system, ag[:41], DT, preload=pre, recorders=[ElementForces(names, name="f")])
            for _ in range(2)]
    assert reads == [tuple(names)]
    assert np.array_equal(runs[0]["f"], runs[1]["f"]) and np.abs(runs[0]["f"]).max() > 0
    other = build_system(deck_model("regularized-coulomb", COULOMB))
    fresh = solve_transient(other, ag[:41], DT, preload=gravity(other), recorders=[ElementForces(names, name="f")])
    assert len(reads) == 2 and np.array_equal(fresh["f"], runs[0]["f"])


def test_a_probe_with_slots_and_no_dict_is_recorded_like_any_other(deck):
    """The loop asks whether a probe's ``sample`` was replaced on the instance; a probe with
    ``__slots__`` (no instance dictionary) has none, and takes the runs of steps at once."""
    system, pre, ag = deck

    class Slotted:
        __slots__ = ("label", "every", "times")

        def __init__(self):
            self.label, self.every, self.times = "slotted", 1, []

        def sample(self, s):
            self.times.append(s.t)

        def sample_many(self, samples):
            self.times.extend(samples.t.tolist())

        def finish(self):
            return {"slotted.time": np.array(self.times)}, {}

    class Spec:
        label, every = "slotted", 1

        def bind(self, ctx):
            return Slotted()

    res = solve_transient(system, ag[:61], DT, preload=pre, recorders=[Spec()])
    assert np.array_equal(res["slotted.time"], res.time) and res.time.size == 61


def test_a_thinned_recorder_keeps_no_run_of_steps_alive(deck, monkeypatch):
    """A probe that keeps every 50th step fills a chunk over 50 runs of steps: it must hold the sampled
    instants only, never the runs' arrays (8 MB each on a large model)."""
    import weakref

    system, pre, ag = deck
    live, most = [], [0]
    real = hht.advance_steps

    def tracked(*args, **kwargs):
        out = real(*args, **kwargs)
        live.append(weakref.ref(out[0]))
        return out

    def progress(_):
        most[0] = max(most[0], sum(ref() is not None for ref in live))

    monkeypatch.setattr(hht, "advance_steps", tracked)
    monkeypatch.setattr(hht, "STEPS_BYTES", 8 * 14 * system.n_free * 70)  # runs of 64 steps, as at 1,000 DOFs
    res = solve_transient(system, band_limited_noise(401, DT, seed=3, amplitude=[6.0, 4.0, 3.0]), DT, preload=pre,
                          recorders=[ConnectorResponse(name="bearings", every=50)], progress=progress)
    assert len(live) > 5 and res["bearings.time"].size == 9
    assert 1 <= most[0] <= 2  # the run being recorded (and the one before it, not yet collected)


def test_a_recorder_raising_in_a_run_of_steps_leaves_the_others_whole(deck):
    """One probe's sample_many raises: the run stops, and the other recorders keep every step up to
    where it stopped (no gap), as the partial result says."""
    from bearingfw.analysis import TransientError

    system, pre, ag = deck

    class Failing(NodalResponse):
        def bind(self, ctx):
            probe = super().bind(ctx)

            class Raising(type(probe)):
                def sample_many(self, samples):
                    if samples.t[-1] > 0.2:
                        raise RuntimeError("recorder failed")
                    super().sample_many(samples)

            probe.__class__ = Raising
            return probe

    node = system.model.nodes[-1].name
    with pytest.raises(TransientError, match="recorder failed") as info:
        solve_transient(system, ag, DT, preload=pre, recorders=[Failing([node], name="n"),
                                                                 ElementForces(["GA0"], name="f")])
    kept = info.value.result
    assert kept is not None and kept["f.time"][-1] == info.value.last_converged > 0.2
    assert np.allclose(np.diff(kept["f.time"]), DT)


def test_a_probe_class_overriding_sample_sees_every_instant(deck):
    """A subclass that overrides ``sample`` but inherits ``sample_many`` gets each instant through its
    own ``sample``, in compiled runs too."""
    system, pre, ag = deck
    seen = []

    class Counting(ElementForces):
        def bind(self, ctx):
            probe = super().bind(ctx)

            class Own(type(probe)):
                def sample(self, s):
                    seen.append(s.t)
                    super().sample(s)

            probe.__class__ = Own
            return probe

    res = solve_transient(system, ag[:81], DT, preload=pre, recorders=[Counting(["GA0"], name="f")])
    assert seen == res["f.time"].tolist() and len(seen) == 81
