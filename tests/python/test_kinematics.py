"""`vito.Kinematics`: forward kinematics by name, against the hopper's foot worked out by hand
from q = [x, z, theta, r]: (x + r sin theta, 0, z - r cos theta)."""

import numpy as np
import pytest

import vito
from conftest import HOPPER


def foot(q):
    x, z, theta, r = q
    return np.array([x + r * np.sin(theta), 0.0, z - r * np.cos(theta)])


def test_a_contact_position_is_the_foot_worked_out_by_hand():
    k = vito.Kinematics(str(HOPPER))
    assert k.contact_names == ["foot_contact"]
    q = [0.1, 0.7, -0.4, 0.35]
    assert np.allclose(k.contact_position("foot_contact", q), foot(q), atol=1e-12)
    assert np.allclose(
        k.point_position("body", q, [0.0, 0.0, -0.35]), foot(q), atol=1e-12
    )
    pose = k.link_pose("body", q)
    # theta turns the body about -y: its pitch is -theta.
    assert pose["roll_pitch_yaw"][1] == pytest.approx(0.4, abs=1e-12)
    assert pose["position"] == pytest.approx([0.1, 0.0, 0.7], abs=1e-12)
    assert np.allclose(k.link_pose("body", np.array(q))["rotation"], pose["rotation"])


def test_a_solutions_knots_give_one_row_each(hopper_solution):
    k = vito.Kinematics(str(HOPPER))
    q = hopper_solution.q
    got = k.contact_position("foot_contact", q)
    assert got.shape == (q.shape[0], 3)
    assert np.allclose(got, np.array([foot(row) for row in q]), atol=1e-12)


def test_unknown_names_and_wrong_lengths_are_errors():
    k = vito.Kinematics(str(HOPPER))
    with pytest.raises(ValueError, match="foot_contact"):
        k.contact_position("toe", [0.0, 0.5, 0.0, 0.5])
    with pytest.raises(ValueError, match="4 coordinates"):
        k.contact_position("foot_contact", [0.0, 0.5, 0.0])
