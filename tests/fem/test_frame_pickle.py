"""era.Frame pickles (the app runs explain in a process pool): the round trip gives the same model, checked again,
without the cached solutions."""

import pickle

import numpy as np
import pytest

import era
from era.discrepancy.frame_model import FrameModel
from era.examples.frames import portal, two_storey


@pytest.mark.parametrize("make", [
    lambda: portal(joint_springs={"B": 3e5}, masses={"E": 2.0}, added_mass_per_length={"beam": 4.0},
                   supports={"A": "fixed", "D": {"kx": "fixed", "ky": "fixed", "kz": "fixed", "rx": "fixed",
                                                 "rz": "fixed", "ry": 1e6}}),
    lambda: two_storey(gravity=(0, 0, -9.81), elements_per_member=3),
    lambda: portal(sensors=[("E", "-z"), ("B", (0.6, 0.0, 0.8)), ("F", "x")]),
])
def test_a_frame_round_trips_through_pickle(make):
    frame = make()
    f0, s0 = frame.modes(4)                       # a cached solution, which is not pickled
    blob = pickle.dumps(frame)
    back = pickle.loads(blob)
    assert isinstance(back, era.Frame) and back is not frame
    assert back.to_dict() == frame.to_dict()
    assert list(back.nodes) == list(frame.nodes) and back.members == frame.members and back.sensors == frame.sensors
    assert "_solutions" not in back.__dict__ and len(blob) < 20_000
    f1, s1 = back.modes(4)
    assert np.array_equal(f0, f1) and np.array_equal(s0, s1)


def test_a_frame_model_with_an_effect_pickles_as_its_frame():
    model = FrameModel.of(portal()).with_params(member_at=("B", "E"), member_factor=0.8)
    back = pickle.loads(pickle.dumps(model.updated_frame))
    assert back.to_dict() == model.updated_frame.to_dict()
    assert np.allclose(back.modes(3)[0], model.exact.modes(3)[0], rtol=1e-12)
