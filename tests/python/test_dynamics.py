"""`vito.Dynamics`: a URDF's dynamics by name, on the hopper worked out by hand (q = [x, z,
theta, r]: the body (mass 3 kg, at (x, z)) and a foot of 0.3 kg at r along the leg turned by
theta about -y, the sliders massless), and its errors."""

import math

import numpy as np
import pytest

import vito
from conftest import ROOT

HOPPER_URDF = ROOT / "problems" / "robots" / "hopper_2d.urdf"


def test_the_hoppers_gravity_and_foot_by_hand():
    d = vito.Dynamics(HOPPER_URDF)
    assert d.coordinate_names == ["x", "z", "theta", "r"]
    assert d.base == "fixed" and d.nq == 4
    q = [0.1, 0.7, -0.4, 0.35]
    x, z, theta, r = q
    foot = [x + r * math.sin(theta), 0.0, z - r * math.cos(theta)]
    assert np.allclose(d.frame_position("foot", q), foot, atol=1e-15)
    m = d.mass_matrix(q)
    assert m.shape == (4, 4) and np.array_equal(m, m.T)
    # The whole robot's weight on z; none on x.
    g = d.gravity(q)
    assert g[0] == 0.0 and g[1] == pytest.approx(9.81 * d.total_mass, rel=1e-15)
    assert d.inverse_dynamics(q, np.zeros(4), np.zeros(4)) == pytest.approx(g, abs=1e-14)
    v = np.array([0.3, -0.2, 1.1, 0.5])
    assert d.kinetic_energy(q, v) == pytest.approx(0.5 * v @ m @ v, rel=1e-14)
    # A floating base leads q with its six coordinates, the same robot lifted onto it.
    floating = vito.Dynamics(HOPPER_URDF, base="floating", gravity=(0.0, 0.0, -1.0))
    assert floating.coordinate_names[:6] == [
        "base_x", "base_y", "base_z", "base_roll", "base_pitch", "base_yaw",
    ]
    assert floating.gravity(np.zeros(10))[2] == pytest.approx(d.total_mass, rel=1e-15)


def test_errors_name_what_is_wrong():
    with pytest.raises(FileNotFoundError):
        vito.Dynamics(ROOT / "no-such.urdf")
    with pytest.raises(ValueError, match="no base `free`"):
        vito.Dynamics(HOPPER_URDF, base="free")
    d = vito.Dynamics(HOPPER_URDF)
    with pytest.raises(ValueError, match="q has 3 values; the robot has 4 coordinates"):
        d.mass_matrix([0.0, 0.5, 0.0])
    with pytest.raises(ValueError, match="no link `toe`; the links are: world, "):
        d.frame_position("toe", [0.0, 0.5, 0.0, 0.5])
    with pytest.raises(ValueError, match=r"shape \(n,\)"):
        d.gravity(np.zeros((2, 4)))
    with pytest.raises(ValueError, match="gravity must be 3 finite numbers"):
        vito.Dynamics(HOPPER_URDF, gravity=(0.0, 0.0, math.nan))
