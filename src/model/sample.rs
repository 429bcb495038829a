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

/// vito's planar hopper of SPEC.md (`problems/robots/hopper_2d.urdf`), fixed base,
/// q = [x, z, theta, r].
pub fn hopper_2d() -> &'static str {
    include_str!("../../problems/robots/hopper_2d.urdf")
}

/// The brick of SPEC.md (`problems/robots/brick.urdf`): use with a floating base.
pub fn brick() -> &'static str {
    include_str!("../../problems/robots/brick.urdf")
}
