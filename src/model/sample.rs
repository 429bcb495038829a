//! Small URDF fixtures shared by tests of the model, the discrete mechanics and the
//! transcription. Each returns the URDF text; all use SI units and gravity along −z.
//!
//! Conventions common to the pendulums: joints rotate about the URDF axis (0 1 0), so the
//! motion lies in the x–z plane, and with Ry(q) a point (0, 0, −l) of a link moves to
//! (−l sin q, 0, −l cos q). Links are uniform rods hanging along −z at q = 0, with
//! Iyy = m l²/12 about their centre (Ixx likewise; Izz a small 1e-3·m so the inertia is
//! positive definite; it plays no part in planar motion).

/// Length (m) of the upper rod of [`double_pendulum`].
pub const DOUBLE_PENDULUM_L1: f64 = 1.0;
/// Mass (kg) of the upper rod of [`double_pendulum`].
pub const DOUBLE_PENDULUM_M1: f64 = 1.0;
/// Length (m) of the lower rod of [`double_pendulum`].
pub const DOUBLE_PENDULUM_L2: f64 = 0.8;
/// Mass (kg) of the lower rod of [`double_pendulum`].
pub const DOUBLE_PENDULUM_M2: f64 = 0.5;

/// The XML of one uniform rod link of mass `m` and length `l` hanging along −z.
fn rod_link(name: &str, m: f64, l: f64) -> String {
    let i = m * l * l / 12.0;
    let izz = 1e-3 * m;
    format!(
        r#"  <link name="{name}">
    <inertial>
      <origin xyz="0 0 {c}" rpy="0 0 0"/>
      <mass value="{m}"/>
      <inertia ixx="{i}" ixy="0" ixz="0" iyy="{i}" iyz="0" izz="{izz}"/>
    </inertial>
  </link>
"#,
        c = -l / 2.0
    )
}

/// A continuous joint about y between `parent` and `child`, at `xyz` in the parent frame.
fn hinge(name: &str, parent: &str, child: &str, xyz: [f64; 3]) -> String {
    format!(
        r#"  <joint name="{name}" type="continuous">
    <parent link="{parent}"/>
    <child link="{child}"/>
    <origin xyz="{} {} {}" rpy="0 0 0"/>
    <axis xyz="0 1 0"/>
  </joint>
"#,
        xyz[0], xyz[1], xyz[2]
    )
}

/// A planar chain of `n` uniform rods (each 1 kg, 1 m) hinged about y below a `base` link
/// (2 kg, inertia diag(0.1, 0.1, 0.1) about its origin, so that with a planar or floating
/// base the mass matrix stays positive definite); joints `joint1..joint<n>` with
/// transmissions on every joint.
pub fn planar_chain(n: usize) -> String {
    let mut xml = String::from("<?xml version=\"1.0\"?>\n<robot name=\"planar_chain\">\n");
    xml += r#"  <link name="base">
    <inertial>
      <mass value="2.0"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/>
    </inertial>
  </link>
"#;
    for k in 1..=n {
        xml += &rod_link(&format!("link{k}"), 1.0, 1.0);
        let parent = if k == 1 {
            "base".to_string()
        } else {
            format!("link{}", k - 1)
        };
        let z = if k == 1 { 0.0 } else { -1.0 };
        xml += &hinge(
            &format!("joint{k}"),
            &parent,
            &format!("link{k}"),
            [0.0, 0.0, z],
        );
    }
    for k in 1..=n {
        xml += &format!(
            "  <transmission name=\"t{k}\" type=\"SimpleTransmission\">\n    <actuator name=\"motor{k}\"/>\n    <joint name=\"joint{k}\"/>\n    <mechanicalReduction>1</mechanicalReduction>\n  </transmission>\n"
        );
    }
    xml + "</robot>\n"
}

/// [`planar_chain`] of `n` rods with damping 0.3 N·m·s/rad on every hinge, so that inputs and
/// damping enter the discrete force.
pub fn damped_chain(n: usize) -> String {
    planar_chain(n).replace(
        "<axis xyz=\"0 1 0\"/>",
        "<axis xyz=\"0 1 0\"/>\n    <dynamics damping=\"0.3\"/>",
    )
}

/// A simple pendulum: one uniform rod (1 kg, 1 m) on joint `joint1` (same as `planar_chain(1)`).
pub fn pendulum() -> String {
    planar_chain(1)
}

/// A double pendulum of uniform rods: `shoulder` carries `upper` (M1, L1), `elbow` at the
/// end of `upper` carries `lower` (M2, L2); no inputs, no damping, no springs.
pub fn double_pendulum() -> String {
    let mut xml = String::from(
        "<?xml version=\"1.0\"?>\n<robot name=\"double_pendulum\">\n  <link name=\"base\"/>\n",
    );
    xml += &rod_link("upper", DOUBLE_PENDULUM_M1, DOUBLE_PENDULUM_L1);
    xml += &rod_link("lower", DOUBLE_PENDULUM_M2, DOUBLE_PENDULUM_L2);
    xml += &hinge("shoulder", "base", "upper", [0.0; 3]);
    xml += &hinge("elbow", "upper", "lower", [0.0, 0.0, -DOUBLE_PENDULUM_L1]);
    xml + "</robot>\n"
}

/// A closed four-bar linkage (Grashof crank-rocker, no change point) in the x–z plane,
/// fixed base, closed at q = 0 and not in equilibrium there (gravity moves it from rest).
/// Ground pivots O = (0, 0, 0) and D = (4.6, 0, −0.2). At q = 0 the crank runs
/// O → A = (0.6, 0, 0.8) (1 m, 1 kg), the coupler A → P = (4.6, 0, 3.8) (5 m, 2 kg), the rocker
/// P → D straight down (4 m, 1.5 kg). Joints `crank`, `coupler`, `rocker` (continuous, axis y)
/// form the tree; the `<loop_joint name="closure">` pins the rocker's end (0, 0, −4) to the
/// ground point D (axis y, so 2 residual rows: x and z). Inertias: Iyy = m L²/12 about the
/// centre of each bar; Ixx = Izz = Iyy (only Iyy matters in planar motion).
pub fn four_bar() -> String {
    let bar = |name: &str, m: f64, len: f64, com: [f64; 3]| {
        let i = m * len * len / 12.0;
        format!(
            r#"  <link name="{name}">
    <inertial>
      <origin xyz="{} {} {}" rpy="0 0 0"/>
      <mass value="{m}"/>
      <inertia ixx="{i}" ixy="0" ixz="0" iyy="{i}" iyz="0" izz="{i}"/>
    </inertial>
  </link>
"#,
            com[0], com[1], com[2]
        )
    };
    let mut xml = String::from(
        "<?xml version=\"1.0\"?>\n<robot name=\"four_bar\">\n  <link name=\"ground\"/>\n",
    );
    xml += &bar("crank_link", 1.0, 1.0, [0.3, 0.0, 0.4]);
    xml += &bar("coupler_link", 2.0, 5.0, [2.0, 0.0, 1.5]);
    xml += &bar("rocker_link", 1.5, 4.0, [0.0, 0.0, -2.0]);
    xml += &hinge("crank", "ground", "crank_link", [0.0; 3]);
    xml += &hinge("coupler", "crank_link", "coupler_link", [0.6, 0.0, 0.8]);
    xml += &hinge("rocker", "coupler_link", "rocker_link", [4.0, 0.0, 3.0]);
    xml += r#"  <loop_joint name="closure" type="continuous">
    <axis xyz="0 1 0"/>
    <link1 link="rocker_link" xyz="0 0 -4" rpy="0 0 0"/>
    <link2 link="ground" xyz="4.6 0 -0.2" rpy="0 0 0"/>
  </loop_joint>
"#;
    xml + "</robot>\n"
}

/// A cart-pole (prismatic-revolute chain): prismatic `slider` along x carries `cart`
/// (2 kg, inertia diag 0.1), continuous `hinge` about y at the cart origin carries `pole`
/// (a uniform rod of 0.5 kg, 1.2 m hanging along −z); transmission on `slider`.
pub fn cart_pole() -> String {
    let mut xml = String::from(
        "<?xml version=\"1.0\"?>\n<robot name=\"cart_pole\">\n  <link name=\"rail\"/>\n",
    );
    xml += r#"  <link name="cart">
    <inertial>
      <mass value="2.0"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/>
    </inertial>
  </link>
  <joint name="slider" type="prismatic">
    <parent link="rail"/>
    <child link="cart"/>
    <axis xyz="1 0 0"/>
    <limit lower="-5" upper="5" effort="50" velocity="10"/>
  </joint>
"#;
    xml += &rod_link("pole", 0.5, 1.2);
    xml += &hinge("hinge", "cart", "pole", [0.0; 3]);
    xml += "  <transmission name=\"t\" type=\"SimpleTransmission\">\n    <joint name=\"slider\"/>\n  </transmission>\n";
    xml + "</robot>\n"
}

/// vito's planar hopper of the reference problem hopper-2d
/// (`problems/robots/hopper_2d.urdf`), fixed base, q = [x, z, theta, r].
pub fn hopper_2d() -> &'static str {
    include_str!("../../problems/robots/hopper_2d.urdf")
}

/// The brick of the reference problem brick-3d (`problems/robots/brick.urdf`): use with a
/// floating base.
pub fn brick() -> &'static str {
    include_str!("../../problems/robots/brick.urdf")
}

/// A gripper as ROS description packages ship it (use with a fixed or floating base): no
/// `<transmission>`; a camera link with mass 0 and a nonzero tensor (a massless frame) and
/// an optical frame without `<inertial>`; a point mass (zero inertia) welded to the palm;
/// a joint and a link both named `thumb`. Coordinates `wrist` (revolute about z) and
/// `left` (the left finger, prismatic along y); three `<mimic>` joints follow them:
/// `right` = −1·left, `tip` (along the right finger's z) = 2·right + 0.003 (a mimic of a
/// mimic), and `thumb` (about a tilted axis) = 0.5·wrist + 0.1.
pub fn gripper() -> &'static str {
    r#"<?xml version="1.0"?>
<robot name="gripper">
  <link name="base">
    <inertial><mass value="2.0"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
  </link>
  <link name="camera_link">
    <inertial><mass value="0"/><inertia ixx="1e-6" ixy="0" ixz="0" iyy="1e-6" iyz="0" izz="1e-6"/></inertial>
  </link>
  <link name="camera_optical_frame"/>
  <joint name="camera_mount" type="fixed">
    <parent link="base"/><child link="camera_link"/><origin xyz="0.1 0 0.05" rpy="0 0.3 0"/>
  </joint>
  <joint name="camera_optical" type="fixed">
    <parent link="camera_link"/><child link="camera_optical_frame"/><origin xyz="0 0 0" rpy="-1.5708 0 -1.5708"/>
  </joint>
  <link name="palm">
    <inertial><origin xyz="0 0 -0.02"/><mass value="0.5"/><inertia ixx="0.002" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.001"/></inertial>
  </link>
  <joint name="wrist" type="revolute">
    <parent link="base"/><child link="palm"/><origin xyz="0 0 -0.1"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="5" velocity="3"/>
  </joint>
  <link name="palm_weight">
    <inertial><mass value="0.2"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>
  </link>
  <joint name="weight_mount" type="fixed">
    <parent link="palm"/><child link="palm_weight"/><origin xyz="0.05 0 0"/>
  </joint>
  <link name="left_finger">
    <inertial><mass value="0.1"/><inertia ixx="1e-4" ixy="0" ixz="0" iyy="1e-4" iyz="0" izz="1e-4"/></inertial>
  </link>
  <joint name="left" type="prismatic">
    <parent link="palm"/><child link="left_finger"/><origin xyz="0 0.02 -0.05"/><axis xyz="0 1 0"/>
    <limit lower="0" upper="0.04" effort="20" velocity="0.1"/>
  </joint>
  <link name="right_finger">
    <inertial><mass value="0.1"/><inertia ixx="1e-4" ixy="0" ixz="0" iyy="1e-4" iyz="0" izz="1e-4"/></inertial>
  </link>
  <joint name="right" type="prismatic">
    <parent link="palm"/><child link="right_finger"/><origin xyz="0 -0.02 -0.05"/><axis xyz="0 1 0"/>
    <limit lower="-0.04" upper="0" effort="20" velocity="0.1"/>
    <mimic joint="left" multiplier="-1"/>
  </joint>
  <link name="tip">
    <inertial><mass value="0.04"/><inertia ixx="1e-5" ixy="0" ixz="0" iyy="1e-5" iyz="0" izz="1e-5"/></inertial>
  </link>
  <joint name="tip" type="prismatic">
    <parent link="right_finger"/><child link="tip"/><origin xyz="0 0 -0.03"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
    <mimic joint="right" multiplier="2" offset="0.003"/>
  </joint>
  <link name="thumb">
    <inertial><origin xyz="0.02 0 0"/><mass value="0.05"/><inertia ixx="2e-5" ixy="0" ixz="0" iyy="3e-5" iyz="0" izz="4e-5"/></inertial>
  </link>
  <joint name="thumb" type="revolute">
    <parent link="palm"/><child link="thumb"/><origin xyz="0.03 0 -0.04" rpy="0.2 -0.1 0.4"/><axis xyz="0.6 0 0.8"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
    <mimic joint="wrist" multiplier="0.5" offset="0.1"/>
  </joint>
</robot>
"#
}
