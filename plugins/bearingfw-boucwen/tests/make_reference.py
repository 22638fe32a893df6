"""Write ``reference_respond.npz``: ``BoucWen.respond`` answers on random calls, frozen.

They were produced by the pure-numpy implementation (before ``respond``'s arithmetic moved to
numba kernels) and are what ``test_reference.py`` compares today's law with. Re-running this
script overwrites them with the current implementation's answers: do that only on purpose.

Each group is one ``respond`` call: a law (random admissible parameters, shared by all
connectors or one value per connector), ``m`` connectors (1, 2 or 5), a committed state from a
random walk and a trial displacement from it (increments from 1e-4 to 60 yield lengths, some
components exactly still, some increments below STILL uy, reversals and sign changes of z).
Exponents: n = 2 (closed form), 1, 1.5, 3, 6 (substeps), and per-bearing mixtures.
"""

from pathlib import Path

import numpy as np

from bearingfw_boucwen import BoucWen

NAMES = ("k", "alpha", "uy", "A", "beta", "gamma", "n")
OUT = Path(__file__).with_name("reference_respond.npz")


def random_parameters(rng, m, n, shared):
    """Parameters for ``m`` connectors: ``(m, 7)`` rows in the order of ``NAMES``."""
    rows = 1 if shared else m
    beta = rng.uniform(0.1, 1.0, rows)
    gamma = beta * np.where(rng.uniform(size=rows) < 0.3, 1.0, rng.uniform(-0.6, 1.0, rows))
    values = np.column_stack([
        10.0 ** rng.uniform(6, 9, rows), np.where(rng.uniform(size=rows) < 0.3, 0.0, rng.uniform(0, 0.9, rows)),
        10.0 ** rng.uniform(-4, -2, rows), rng.uniform(0.5, 2.0, rows), beta, gamma,
        np.broadcast_to(n, (rows,)) if np.ndim(n) == 0 else np.asarray(n, dtype=float)[:rows],
    ])  # fmt: skip
    return np.repeat(values, m, axis=0) if shared else values


def law_of(values, dims):
    """The law of ``(m, 7)`` parameter rows: scalar parameters if all rows are equal."""
    if (values == values[0]).all():
        return BoucWen(**{name: float(v) for name, v in zip(NAMES, values[0])}, dims=dims)
    return BoucWen(**{name: values[:, i].copy() for i, name in enumerate(NAMES)}, dims=dims)


def groups(rng):
    exponents = [2.0, 2.0, 1.0, 1.5, 3.0, 6.0]
    for dims in (1, 2):
        for n in exponents:
            for m, shared in ((1, True), (2, True), (5, True), (5, False)):
                yield dims, n, m, shared
        for n in ([2.0, 1.0, 2.0, 3.0, 2.0], [1.5, 2.0, 2.0, 2.0, 2.0]):  # mixtures: both paths in one call
            yield dims, n, 5, False


def main():
    rng = np.random.default_rng(20261126)
    records = {key: [] for key in ("group", "dims", "params", "z0", "u0", "u", "force", "tangent", "z")}
    group = 0
    for dims, n, m, shared in groups(rng):
        values = random_parameters(rng, m, n, shared)
        law = law_of(values, dims)
        scale = np.broadcast_to(law.z_max * law.uy / law.A, (m,)).reshape(m, 1)  # the yield length
        state, u = law.initial_state(m), np.zeros((m, dims))
        for call in range(3):  # three trials from three committed states of one walk
            for _ in range(rng.integers(1, 4)):
                u = u + rng.normal(size=(m, dims)) * scale * rng.uniform(0.3, 3.0, (m, 1))
                state = law.respond(state, u, np.ones(m), 0.01).state
            du = rng.normal(size=(m, dims)) * scale * 10.0 ** rng.uniform(-4.0, np.log10(60.0), (m, 1))
            if dims == 2 and call == 1:
                du[0, rng.integers(2)] = 0.0  # a component that does not move
            if call == 2 and m > 1:
                du[1] *= 1e-210  # below STILL uy
            if call == 0 and m > 1:
                du[-1] = 0.0
            trial = u + du
            response = law.respond(state, trial, np.ones(m), 0.01)
            for key, value in (("params", values), ("z0", state["z"]), ("u0", state["u"]), ("u", trial),
                               ("force", response.force), ("tangent", response.tangent),
                               ("z", response.state["z"])):  # fmt: skip
                records[key].append(np.asarray(value, dtype=float).reshape(m, -1))
            records["group"].append(np.full(m, group))
            records["dims"].append(np.full(m, dims))
            group += 1

    def pad(blocks, width):
        return np.concatenate([np.pad(b, ((0, 0), (0, width - b.shape[1])), constant_values=np.nan) for b in blocks])

    arrays = {key: pad(records[key], w) for key, w in (("params", 7), ("z0", 2), ("u0", 2), ("u", 2), ("force", 2),
                                                         ("tangent", 4), ("z", 2))}  # fmt: skip
    arrays["group"] = np.concatenate(records["group"])
    arrays["dims"] = np.concatenate(records["dims"])
    np.savez_compressed(OUT, **arrays)
    print(f"{OUT}: {group} calls, {len(arrays['group'])} connector rows, {OUT.stat().st_size} bytes")


if __name__ == "__main__":
    main()
