//! The URDF loader rejects malformed models with a message that names the culprit, repairs
//! only what is unambiguous, reports what it ignores, and never panics on input.

use vito::model::{BaseType, Model, ModelError, mass_matrix, sample};
use vito::random::SeededRng;

/// A link with a valid inertial.
fn link(name: &str) -> String {
    format!(
        r#"<link name="{name}"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>"#
    )
}

fn joint(name: &str, kind: &str, parent: &str, child: &str) -> String {
    format!(
        r#"<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>"#
    )
}

fn robot(body: &str) -> String {
    format!("<?xml version=\"1.0\"?><robot name=\"r\">{body}</robot>")
}

fn reject(xml: &str) -> (ModelError, String) {
    match Model::from_urdf_str(xml, BaseType::Fixed) {
        Ok(_) => panic!("accepted a malformed URDF:\n{xml}"),
        Err(e) => {
            let msg = e.to_string();
            (e, msg)
        }
    }
}

#[test]
fn missing_parent_and_child_links_are_named() {
    let xml = robot(&(link("a") + &joint("j1", "revolute", "ghost", "a")));
    let (e, msg) = reject(&xml);
    assert!(
        matches!(e, ModelError::MissingLink { role: "parent", .. }),
        "{e:?}"
    );
    assert!(msg.contains("'j1'") && msg.contains("'ghost'"), "{msg}");
    let xml = robot(&(link("a") + &joint("j2", "revolute", "a", "phantom")));
    let (e, msg) = reject(&xml);
    assert!(
        matches!(e, ModelError::MissingLink { role: "child", .. }),
        "{e:?}"
    );
    assert!(msg.contains("'j2'") && msg.contains("'phantom'"), "{msg}");
}

#[test]
fn cycles_are_rejected() {
    // Every link has a parent: no root at all.
    let body = link("a")
        + &link("b")
        + &link("c")
        + &joint("ab", "revolute", "a", "b")
        + &joint("bc", "revolute", "b", "c")
        + &joint("ca", "revolute", "c", "a");
    let (e, msg) = reject(&robot(&body));
    assert!(matches!(e, ModelError::Cycle { .. }), "{e:?}");
    assert!(msg.contains("cycle") && msg.contains("'a'"), "{msg}");
    // A root plus a detached cycle.
    let body = link("root")
        + &link("p")
        + &link("q")
        + &joint("pq", "revolute", "p", "q")
        + &joint("qp", "revolute", "q", "p");
    let (e, msg) = reject(&robot(&body));
    assert!(matches!(e, ModelError::Cycle { .. }), "{e:?}");
    assert!(msg.contains("'p'") || msg.contains("'q'"), "{msg}");
    // A link with two parents.
    let body = link("a")
        + &link("b")
        + &link("c")
        + &joint("ab", "revolute", "a", "b")
        + &joint("cb", "revolute", "c", "b");
    let (e, msg) = reject(&robot(&body));
    assert!(matches!(e, ModelError::MultipleParents { .. }), "{e:?}");
    assert!(
        msg.contains("'b'") && msg.contains("'ab'") && msg.contains("'cb'"),
        "{msg}"
    );
}

#[test]
fn multiple_roots_are_rejected() {
    let body = link("a") + &link("b") + &link("island");
    let body = body + &joint("ab", "fixed", "a", "b");
    let (e, msg) = reject(&robot(&body));
    assert!(matches!(e, ModelError::MultipleRoots { .. }), "{e:?}");
    assert!(msg.contains("a") && msg.contains("island"), "{msg}");
}

#[test]
fn negative_and_non_finite_masses_are_rejected() {
    for mass in ["-2.5", "nan", "inf"] {
        let bad = format!(
            r#"<link name="heavy_nothing"><inertial><mass value="{mass}"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>"#
        );
        let body = link("base") + &bad + &joint("j", "revolute", "base", "heavy_nothing");
        let (e, msg) = reject(&robot(&body));
        assert!(matches!(e, ModelError::Invalid { .. }), "{e:?}");
        assert!(
            msg.contains("'heavy_nothing'") || msg.contains("\"heavy_nothing\""),
            "{msg}"
        );
    }
}

/// A moving body whose inertia is not positive definite is kept as written (as ROS's
/// parsers and Pinocchio keep it) with a warning naming it, and a second warning when the
/// mass matrix is singular; a mass matrix with a negative eigenvalue is refused.
#[test]
fn non_positive_definite_inertias_are_named() {
    let model_with = |inertia: &str| {
        let bad = format!(
            r#"<link name="wobbly"><inertial><mass value="1"/><inertia {inertia}/></inertial></link>"#
        );
        robot(&(link("base") + &bad + &joint("j", "revolute", "base", "wobbly")))
    };
    // Negative kinetic energy about the joint's axis (y): refused.
    let (e, msg) = reject(&model_with(
        r#"ixx="1" ixy="0" ixz="0" iyy="-1" iyz="0" izz="1""#,
    ));
    assert!(matches!(e, ModelError::Invalid { .. }), "{e:?}");
    assert!(
        msg.contains("\"wobbly\"")
            && msg.contains("positive definite")
            && msg.contains("negative eigenvalue (-1e0) along `j`"),
        "{msg}"
    );
    // Indefinite, but 1 about the axis: loads, the mass matrix is fine.
    let m = Model::from_urdf_str(
        &model_with(r#"ixx="1" ixy="2" ixz="0" iyy="1" iyz="0" izz="1""#),
        BaseType::Fixed,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let w = m.warnings().join("\n");
    assert!(
        w.contains("<link name=\"wobbly\"> <inertial>: the rigid body has an inertia that is not positive definite")
            && w.contains("kept as written")
            && !w.contains("singular"),
        "{w}"
    );
    assert_eq!(mass_matrix(&m, &[0.3])[(0, 0)], 1.0);
    // Zero: loads, and the mass matrix is singular along the joint.
    let m = Model::from_urdf_str(
        &model_with(r#"ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0""#),
        BaseType::Fixed,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let w = m.warnings().join("\n");
    assert!(
        w.contains("\"wobbly\"")
            && w.contains("mass matrix is singular at the nominal pose along `j`"),
        "{w}"
    );
}

#[test]
fn unsupported_joint_types_are_rejected() {
    for kind in ["floating", "planar"] {
        let body = link("base") + &link("free") + &joint("loose", kind, "base", "free");
        let (e, msg) = reject(&robot(&body));
        assert!(
            matches!(e, ModelError::UnsupportedJointType { .. }),
            "{e:?}"
        );
        assert!(msg.contains("'loose'") && msg.contains(kind), "{msg}");
    }
    let body = link("base") + &link("b") + &joint("weird", "helical", "base", "b");
    let (_, msg) = reject(&robot(&body));
    assert!(msg.contains("helical") || msg.contains("weird"), "{msg}");
}

#[test]
fn other_malformed_inputs_are_named() {
    // Zero axis.
    let body = link("base")
        + &link("b")
        + r#"<joint name="spin" type="revolute"><parent link="base"/><child link="b"/><axis xyz="0 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>"#;
    let (e, msg) = reject(&robot(&body));
    assert!(
        matches!(e, ModelError::BadAxis { .. }) && msg.contains("'spin'"),
        "{msg}"
    );
    // Duplicate link.
    let (e, msg) = reject(&robot(&(link("twin") + &link("twin"))));
    assert!(
        matches!(e, ModelError::DuplicateName { .. }) && msg.contains("'twin'"),
        "{msg}"
    );
    // Spring on an unknown joint.
    let body = link("base")
        + &link("b")
        + &joint("j", "revolute", "base", "b")
        + r#"<force_element name="k1"><torsional_spring stiffness="1" rest_angle="0"><joint name="nope"/></torsional_spring></force_element>"#;
    let (_, msg) = reject(&robot(&body));
    assert!(msg.contains("'k1'") && msg.contains("'nope'"), "{msg}");
    // Spring without stiffness.
    let body = link("base")
        + &link("b")
        + &joint("j", "revolute", "base", "b")
        + r#"<force_element name="k2"><torsional_spring rest_angle="0"><joint name="j"/></torsional_spring></force_element>"#;
    let (_, msg) = reject(&robot(&body));
    assert!(msg.contains("'k2'") && msg.contains("stiffness"), "{msg}");
    // Loop joint to an unknown link.
    let body = link("base")
        + &link("b")
        + &joint("j", "revolute", "base", "b")
        + r#"<loop_joint name="pin" type="continuous"><axis xyz="0 1 0"/><link1 link="b" xyz="0 0 0"/><link2 link="moon" xyz="0 0 0"/></loop_joint>"#;
    let (_, msg) = reject(&robot(&body));
    assert!(msg.contains("'pin'") && msg.contains("'moon'"), "{msg}");
    // Not XML.
    let (e, _) = reject("<robot name=\"r\"><link name=\"a\">");
    assert!(matches!(e, ModelError::Xml { .. }), "{e:?}");
    // No links.
    let (e, _) = reject(&robot(""));
    assert!(matches!(e, ModelError::NoLinks), "{e:?}");
}

#[test]
fn unambiguous_repairs_are_made_and_reported() {
    let body = link("base")
        + &link("b")
        + r#"<joint name="j" type="Revolute"><parent link="base"/><child link="b"/><origin xyz="1, 0, 0"/><axis xyz="0 1 0"/><limit lower="-pi/4" upper="2*pi"/></joint>"#
        + r#"<frame link="b" name="tip" xyz="0 0 1"/>"#;
    let m = Model::from_urdf_str(&robot(&body), BaseType::Fixed).unwrap_or_else(|e| panic!("{e}"));
    let (lo, hi) = m.coordinate_limits()[0];
    assert!((lo + std::f64::consts::FRAC_PI_4).abs() < 1e-15);
    assert!((hi - 2.0 * std::f64::consts::PI).abs() < 1e-15);
    let w = m.warnings().join("\n");
    for needle in ["velocity", "effort", "commas", "Revolute", "pi/4", "<frame"] {
        assert!(w.contains(needle), "no warning about {needle}:\n{w}");
    }
}

#[test]
fn truncated_documents_never_panic() {
    let xml = sample::four_bar();
    let complete = xml.trim_end().len();
    let mut accepted = 0;
    for end in (0..complete).filter(|&i| xml.is_char_boundary(i)) {
        if Model::from_urdf_str(&xml[..end], BaseType::Floating).is_ok() {
            accepted += 1;
        }
    }
    // No strict prefix of the document (up to its trailing newline) is valid.
    assert_eq!(accepted, 0);
    assert!(Model::from_urdf_str(&xml, BaseType::Floating).is_ok());
}

#[test]
fn mutated_documents_never_panic() {
    // Replace one character of valid URDFs by a character that matters to XML or numbers.
    let docs = [
        sample::four_bar(),
        sample::hopper_2d().to_string(),
        sample::brick().to_string(),
    ];
    let alphabet: Vec<char> = "<>/=\"' -0.9eEx,pi".chars().collect();
    let mut rng = SeededRng::new(1);
    let mut next = |n: usize| rng.index(n);
    for _ in 0..1000 {
        let doc = &docs[next(docs.len())];
        let chars: Vec<char> = doc.chars().collect();
        let mut mutated = chars.clone();
        mutated[next(chars.len())] = alphabet[next(alphabet.len())];
        let text: String = mutated.into_iter().collect();
        for base in [BaseType::Fixed, BaseType::Planar, BaseType::Floating] {
            let _ = Model::from_urdf_str(&text, base);
        }
    }
}

/// A transmission's `mechanicalReduction` of 0, NaN or ±inf is refused by name; 2 loads
/// (with a warning that vito uses 1).
#[test]
fn degenerate_mechanical_reductions_are_refused() {
    let body = |reduction: &str| {
        robot(
            &(link("a")
                + &link("b")
                + &joint("hinge", "revolute", "a", "b")
                + &format!(
                    r#"<transmission name="drive"><joint name="hinge"/><mechanicalReduction>{reduction}</mechanicalReduction></transmission>"#
                )),
        )
    };
    for bad in ["0", "-0", "NaN", "inf", "-inf"] {
        let (_, msg) = reject(&body(bad));
        assert!(
            msg.contains("drive") && msg.contains("mechanicalReduction"),
            "{bad}: {msg}"
        );
    }
    let model = Model::from_urdf_str(&body("2"), BaseType::Fixed).unwrap();
    assert!(
        model
            .warnings()
            .iter()
            .any(|w| w.contains("mechanicalReduction 2 ignored")),
        "{:?}",
        model.warnings()
    );
}
