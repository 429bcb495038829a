"""Pinocchio as an independent oracle for vito's rigid-body dynamics: a URDF loaded by both,
with vito's coordinates mapped onto Pinocchio's joints (shared by the tests of
test_pinocchio.py).

The mapping, coordinate by coordinate:

- vito's floating base is the pose Trans(x, y, z)·Rz(yaw)·Ry(pitch)·Rx(roll) with coordinates
  q = [base_x, base_y, base_z, base_roll, base_pitch, base_yaw, joints...]. Pinocchio's
  model here starts with a chain of six one-degree-of-freedom joints PX, PY, PZ, RZ, RY, RX
  (massless bodies between them, each joint about its axis in the frame the ones before it
  left), named base_x, base_y, base_z, base_yaw, base_pitch, base_roll, and the URDF's tree
  is appended at the chain's end (`pinocchio.appendModel`, which carries the root link's
  inertia over): the same pose, with roll and yaw in swapped places. Each joint's velocity
  is the rate of its coordinate, so Pinocchio's v is vito's q̇ under the same permutation,
  and M, g, the inverse dynamics and ∂T/∂q are the same matrices and vectors permuted. (A
  FreeFlyer would take a quaternion and a body-frame twist instead and need the map between
  the rates; a JointModelComposite of the six gives the same M, g and RNEA, but Pinocchio's
  derivative algorithms, computeRNEADerivatives and computeCoriolisMatrix, gave a ∂T/∂q
  off by 1e-3 on it, which a chain of ordinary joints does not.)
- the planar base Trans(x, 0, z)·Ry(pitch), q = [base_x, base_z, base_pitch]: a chain
  PX, PZ, RY in vito's order.
- the URDF's joints, by name: vito lists them in document order, Pinocchio depth first.
  A continuous joint is one coordinate θ in vito and (cos θ, sin θ) in Pinocchio's q (one
  velocity). A `<mimic>` joint has no coordinate in vito and is Pinocchio's
  JointModelMimic (`mimic=True`), which has none either.

Pinocchio reads URDFs with urdfdom, stricter than vito's reader: the copy it is given has
its `<collision>` and `<visual>` elements removed (not part of the dynamics), infinite
`<limit>` values (vito's normalised files write `inf` for "no limit") replaced by 1e10, and
XML namespaces (Drake's) dropped.
"""

from __future__ import annotations

import math
import pathlib
import xml.etree.ElementTree as ET

import numpy as np

import vito

BASE_COORDINATES_IN_PINOCCHIO_ORDER = {
    "fixed": [],
    "planar": ["base_x", "base_z", "base_pitch"],
    "floating": ["base_x", "base_y", "base_z", "base_yaw", "base_pitch", "base_roll"],
}


def pinocchio_urdf_text(path) -> str:
    """The URDF at `path` as urdfdom takes it (see the module's docstring)."""
    root = ET.parse(path).getroot()
    for element in root.iter():
        if element.tag.startswith("{"):
            element.tag = element.tag.split("}", 1)[1]
        for key in [k for k in element.attrib if k.startswith("{")]:
            del element.attrib[key]
        for child in list(element):
            if child.tag.split("}")[-1] in ("collision", "visual"):
                element.remove(child)
    for limit in root.iter("limit"):
        for key, value in limit.attrib.items():
            try:
                x = float(value)
            except ValueError:
                continue
            if not math.isfinite(x):
                limit.set(key, repr(math.copysign(1e10, x)))
    return ET.tostring(root, encoding="unicode")


BASE_JOINTS = {
    "fixed": [],
    "planar": ["PX", "PZ", "RY"],
    "floating": ["PX", "PY", "PZ", "RZ", "RY", "RX"],
}


def build_model(pin, xml, base, names):
    """Pinocchio's model of the URDF text `xml` on `base`, the base's joints named `names`
    (see the module's docstring)."""
    tree = pin.buildModelFromXML(xml, True)  # True: <mimic> joints as JointModelMimic
    if base == "fixed":
        return tree
    chain = pin.Model()
    parent = 0
    for kind, name in zip(BASE_JOINTS[base], names, strict=True):
        joint = getattr(pin, f"JointModel{kind}")()
        parent = chain.addJoint(parent, joint, pin.SE3.Identity(), name)
    mount = chain.addFrame(
        pin.Frame("base_mount", parent, 0, pin.SE3.Identity(), pin.FrameType.OP_FRAME)
    )
    return pin.appendModel(chain, tree, mount, pin.SE3.Identity())


class Pair:
    """One robot in vito (`self.vito`, a vito.Dynamics) and in Pinocchio (`self.model`), with
    the maps between their coordinates."""

    def __init__(self, pin, urdf, base, gravity=(0.0, 0.0, -9.81), base_order=None):
        self.pin = pin
        self.vito = vito.Dynamics(str(urdf), base=base, gravity=list(gravity))
        # `base_order` names the base's joints otherwise: a test gives a wrong map on purpose.
        order = base_order or BASE_COORDINATES_IN_PINOCCHIO_ORDER[base]
        self.model = build_model(pin, pinocchio_urdf_text(urdf), base, order)
        self.model.gravity.linear = np.array(gravity, dtype=float)
        self.data = self.model.createData()
        names = self.vito.coordinate_names
        velocity_index = {}
        for j in range(1, self.model.njoints):
            joint = self.model.joints[j]
            if joint.nv == 1:  # a mimic joint has none
                velocity_index[self.model.names[j]] = joint.idx_v
        if sorted(velocity_index) != sorted(names) or self.model.nv != len(names):
            raise AssertionError(
                f"coordinates differ: vito {names}, Pinocchio {sorted(velocity_index)}"
            )
        # v_pinocchio[P] = v_vito: P[i] is vito coordinate i's Pinocchio velocity index.
        self.P = np.array([velocity_index[name] for name in names])
        self.joint_of_velocity = {}
        for j in range(1, self.model.njoints):
            joint = self.model.joints[j]
            for k in range(joint.nv):
                self.joint_of_velocity[joint.idx_v + k] = (joint, k)

    def make_heavier(self, factor):
        """Every body of Pinocchio's model `factor` times as heavy (its centre of mass and
        rotational inertia kept)."""
        for j in range(self.model.njoints):
            inertia = self.model.inertias[j]
            self.model.inertias[j] = self.pin.Inertia(
                factor * inertia.mass, inertia.lever, inertia.inertia
            )
        self.data = self.model.createData()

    @property
    def n(self):
        return len(self.P)

    def q(self, q_vito):
        """Pinocchio's configuration for vito's q."""
        q = self.pin.neutral(self.model)
        for i, p in enumerate(self.P):
            joint, k = self.joint_of_velocity[p]
            if joint.nq == 2 * joint.nv:  # continuous: (cos θ, sin θ)
                q[joint.idx_q : joint.idx_q + 2] = [math.cos(q_vito[i]), math.sin(q_vito[i])]
            else:
                q[joint.idx_q + k] = q_vito[i]
        return q

    def v(self, v_vito):
        """Pinocchio's velocity (or acceleration) for vito's."""
        v = np.zeros(self.model.nv)
        v[self.P] = v_vito
        return v

    def to_vito(self, vector):
        """A Pinocchio velocity-space vector (a generalised force) in vito's order."""
        return np.asarray(vector)[self.P]

    def mass_matrix(self, q_vito):
        m = self.pin.crba(self.model, self.data, self.q(q_vito))
        m = np.triu(m) + np.triu(m, 1).T  # crba fills the upper triangle
        return m[np.ix_(self.P, self.P)]

    def gravity(self, q_vito):
        return self.to_vito(
            self.pin.computeGeneralizedGravity(self.model, self.data, self.q(q_vito))
        )

    def inverse_dynamics(self, q_vito, v_vito, a_vito):
        return self.to_vito(
            self.pin.rnea(self.model, self.data, self.q(q_vito), self.v(v_vito), self.v(a_vito))
        )

    def kinetic_energy_gradient(self, q_vito, v_vito):
        """∂T/∂q = ½ vᵀ (∂M/∂q_j) v for each j, from the derivative of M(q)a + g(q) in q
        at a = v (K[:, j] = (∂M/∂q_j) v) less the one at a = 0."""
        q, v = self.q(q_vito), self.v(v_vito)
        zero = np.zeros(self.model.nv)
        with_a = self.pin.computeRNEADerivatives(self.model, self.data, q, zero, v)[0].copy()
        without = self.pin.computeRNEADerivatives(self.model, self.data, q, zero, zero)[0]
        k = with_a - without
        return self.to_vito(0.5 * k.T @ v)

    def frame(self, link, q_vito):
        """(rotation, position) of `link`'s frame (its BODY frame)."""
        self.pin.framesForwardKinematics(self.model, self.data, self.q(q_vito))
        placement = self.data.oMf[self.model.getFrameId(link, self.pin.BODY)]
        return placement.rotation.copy(), placement.translation.copy()

    def point_jacobian(self, link, point, q_vito):
        """The world-frame Jacobian (3 × n, vito's order) of `point` fixed in `link`."""
        pin = self.pin
        body = self.model.getFrameId(link, pin.BODY)
        frame = self.model.frames[body]
        name = f"{link}:point"
        if not self.model.existFrame(name):
            self.model.addFrame(
                pin.Frame(
                    name,
                    frame.parentJoint,
                    body,
                    frame.placement * pin.SE3(np.eye(3), np.asarray(point, dtype=float)),
                    pin.FrameType.OP_FRAME,
                )
            )
            self.data = self.model.createData()
        f = self.model.getFrameId(name)
        q = self.q(q_vito)
        pin.computeJointJacobians(self.model, self.data, q)
        pin.framesForwardKinematics(self.model, self.data, q)
        jac = pin.getFrameJacobian(self.model, self.data, f, pin.LOCAL_WORLD_ALIGNED)[:3]
        return jac[:, self.P], self.data.oMf[f].translation.copy()


def example_robot_data_dir() -> pathlib.Path | None:
    """Where the PyPI package example-robot-data keeps its robots (None when missing)."""
    import importlib.metadata

    try:
        dist = importlib.metadata.distribution("example-robot-data")
    except importlib.metadata.PackageNotFoundError:
        return None
    path = pathlib.Path(dist.locate_file("cmeel.prefix/share/example-robot-data/robots"))
    return path if path.is_dir() else None
