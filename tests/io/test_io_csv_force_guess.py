"""A CSV whose header names say nothing (t,ch1,ch2; time,a,b) still gets its hammer proposed from the values: the
channel that is a short pulse while the others ring on (era.io.records.hammer_channel), so the kind proposed is
'input and output' (io). A response marked by its unit, or a record with no pulse, is never taken for a force."""

import sys
from pathlib import Path

import numpy as np
import pytest

import era
from era.io.preview import preview

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "markov"))
from chain_sim import chain, hammer_decay, simulate  # noqa: E402

DT = 0.01


def hit(n: int = 2000) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A hammer's half-sine pulse (4 samples, at sample 20) on mass 3 of the chain: (force (n,), acc (n, 3), f_hz)."""
    ad, bd, cd, dd, f_modes, _ = chain(DT)
    force = np.zeros(n)
    force[20:24] = np.sin(np.pi * (np.arange(4) + 0.5) / 4)
    return force, simulate(ad, bd[:, 2:], cd, dd[:, 2:], force[:, None]), f_modes


def csv(header: str, columns: np.ndarray) -> bytes:
    rows = [f"{k * DT:.4f}," + ",".join(f"{v:.10e}" for v in r) for k, r in enumerate(columns)]
    return ("\n".join([header] + rows) + "\n").encode()


@pytest.mark.parametrize("header, force_at", [("t,ch1,ch2,ch3,ch4", 0), ("time,a,b,c,d", 2)])
def test_generic_names_get_the_hammer_proposed_from_the_values(header, force_at):
    force, acc, f_modes = hit()
    table = np.insert(acc, force_at, force, axis=1)
    raw = csv(header, table)
    names = header.split(",")[1:]
    pv = preview(raw, name="hit.csv")
    assert [c.force for c in pv.channels] == [k == force_at for k in range(4)] and pv.kind == "io"
    assert f"{names[force_at]!r} proposed as the force (a short pulse" in pv.described[0]
    ds = era.load(raw, name="hit.csv", n_observer=20)  # nothing said: the proposal is what era.load does
    assert ds.source["kind"] == "io" and ds.data.inputs == (names[force_at],)
    assert ds.data.outputs == tuple(n for k, n in enumerate(names) if k != force_at)
    model = era.identify(ds.data, rows=20, cols=20).realize(order=6)
    np.testing.assert_allclose(np.sort(model.frequency_hz), f_modes, rtol=1e-4)


def test_no_pulse_or_a_response_unit_is_no_force():
    y, _ = hammer_decay(1500, 2, DT)  # free decay on every channel: no short pulse
    pv = preview(csv("t,ch1,ch2,ch3", y), name="decay.csv")
    assert not any(c.force for c in pv.channels) and pv.kind == "decay"
    force, acc, _ = hit()
    marked = csv("t,a1 [g],a2 [g],a3 [g],a4 [g]", np.column_stack([force, acc]))  # the unit says 'response'
    assert not any(c.force for c in preview(marked, name="g.csv").channels)
    named = csv("t,hammer,a,b,c", np.column_stack([force, acc]))  # a name that says it: one force, as before
    assert [c.force for c in preview(named, name="n.csv").channels] == [True, False, False, False]
    volts = csv("t,ch1 (mV),ch2 (mV),ch3 (mV),ch4 (mV)", np.column_stack([force, acc]))  # a raw transducer signal
    assert [c.force for c in preview(volts, name="v.csv").channels] == [True, False, False, False]
