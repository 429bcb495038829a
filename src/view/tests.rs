use super::*;
use crate::model::link_pose;
use svg::strip_frames;

fn hopper_scene() -> (crate::problem::LoadedProblem, Scene) {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("problems/hopper_2d.toml");
    let problem = crate::problem::load(&file, &[]).unwrap();
    let scene = scene(&problem).unwrap();
    (problem, scene)
}

/// A motion of `n` knots h apart with a swinging leg and rising base.
fn motion_of(
    problem: &crate::problem::LoadedProblem,
    n: usize,
    h: f64,
    simulation: bool,
) -> Motion {
    let nq = problem.robot.coordinates.len();
    let q: Vec<Vec<f64>> = (0..n)
        .map(|k| {
            let s = k as f64 / n as f64;
            let mut q = problem.spec.q_initial.clone();
            for (j, v) in q.iter_mut().enumerate().take(nq) {
                *v += 0.3 * s * (j as f64 + 1.0).sin();
            }
            q
        })
        .collect();
    Motion {
        name: "m".into(),
        detail: "d".into(),
        standing: if simulation {
            Standing::Simulation
        } else {
            Standing::Solved
        },
        times: (0..n).map(|k| k as f64 * h).collect(),
        q,
        normal: vec![vec![1.0]; n - 1],
        friction: vec![vec![vec![0.5, 0.25]]; n - 1],
    }
}

#[test]
fn each_link_pose_per_frame_is_the_models_forward_kinematics() {
    let (problem, scene) = hopper_scene();
    let motion = motion_of(&problem, 30, 0.05, false);
    let drawing = drawing(&scene, std::slice::from_ref(&motion));
    let model = scene.mechanics.model();
    let frames = &drawing.frames[0];
    assert_eq!(frames.len(), 30, "a plan keeps every knot");
    // And through the page's JSON, as the page reads it (rounded to 1e-5 of the robot).
    let data = page_data(&scene, std::slice::from_ref(&motion), &drawing);
    let tol = 1e-5 * drawing.size;
    for (f, frame) in frames.iter().enumerate() {
        assert_eq!(frame.knot, f);
        for l in 0..model.link_names().len() {
            let (r, p) = link_pose(model, LinkId(l), &motion.q[f]);
            let (fp, fq) = frame.links[l];
            let fr = rotation_of(&fq);
            for i in 0..3 {
                assert!((fp[i] - p[i]).abs() < 1e-12, "frame {f} link {l}");
                for j in 0..3 {
                    assert!((fr[i][j] - r[i][j]).abs() < 1e-12, "frame {f} link {l}");
                }
            }
            let page = &data["tracks"][0]["poses"][f];
            for i in 0..3 {
                let v = page[7 * l + i].as_f64().unwrap();
                assert!(
                    (v - p[i]).abs() <= tol,
                    "page frame {f} link {l}: {v} vs {}",
                    p[i]
                );
            }
        }
        // The contact point is the model's, and on flat ground the impulse is the normal
        // along +z and the friction +x − (−x) along x.
        let c = scene.mechanics.contact_position(0, &motion.q[f]);
        assert_eq!(frame.contacts[0], c);
        let expected = if f + 1 < 30 {
            [[0.0, 0.0, 1.0], [0.25, 0.0, 0.0]]
        } else {
            [[0.0; 3]; 2]
        };
        assert_eq!(frame.impulses[0], expected);
    }
}

#[test]
fn a_decimated_simulation_keeps_its_first_and_last_step() {
    // 2 s at 2 kHz: 4001 steps, at most 60 per second of motion (121 frames).
    let times: Vec<f64> = (0..4001).map(|k| k as f64 * 5e-4).collect();
    let kept = frame_indices(&times, true, 1.0);
    assert_eq!(kept.first(), Some(&0));
    assert_eq!(kept.last(), Some(&4000));
    assert!(kept.len() <= 122 && kept.len() >= 110, "{}", kept.len());
    assert!(kept.windows(2).all(|w| w[0] < w[1]));
    // An odd step count: the last step is kept even off the spacing.
    let times: Vec<f64> = (0..3999).map(|k| k as f64 * 5e-4).collect();
    let kept = frame_indices(&times, true, 1.0);
    assert_eq!(kept.last(), Some(&3998));
    // 100 ms in milliseconds (HAMR): about MIN_FRAMES (the steps' grid rounds the spacing up).
    let times: Vec<f64> = (0..2001).map(|k| k as f64 * 0.05).collect();
    let kept = frame_indices(&times, true, crate::problem::units::seconds_per("ms"));
    assert!(
        kept.len() >= MIN_FRAMES * 9 / 10 && kept.len() <= MIN_FRAMES + 1,
        "{}",
        kept.len()
    );
    // A plan keeps every knot.
    assert_eq!(frame_indices(&times, false, 1.0).len(), 2001);
}

#[test]
fn quaternions_round_trip_rotations() {
    for rpy in [
        [0.1, -0.7, 2.9],
        [3.1, 0.2, -3.0],
        [0.0, 1.5, 0.0],
        [3.0, 0.0, -2.5],
    ] {
        let (sr, cr) = f64::sin_cos(rpy[0]);
        let (sp, cp) = f64::sin_cos(rpy[1]);
        let (sy, cy) = f64::sin_cos(rpy[2]);
        let r = [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ];
        let back = rotation_of(&quaternion(&r));
        for i in 0..3 {
            for j in 0..3 {
                assert!((back[i][j] - r[i][j]).abs() < 1e-12, "{rpy:?}");
            }
        }
    }
}

#[test]
fn the_page_is_self_contained_and_its_strip_draws_n_poses() {
    let (problem, scene) = hopper_scene();
    let motion = motion_of(&problem, 20, 0.05, false);
    let drawing = drawing(&scene, std::slice::from_ref(&motion));
    let html = page(&scene, std::slice::from_ref(&motion), &drawing);
    assert!(!html.contains(DATA_MARK));
    for remote in ["http://", "https://", "//cdn", "src=\"", "import "] {
        assert!(!html.contains(remote), "the page names `{remote}`");
    }
    let svg = strip_svg(&scene, &drawing, &motion, 5, StripLayout::Panels);
    assert_eq!(svg.matches("<g class=\"pose\"").count(), 5);
    assert!(!svg.contains("NaN"));
}

/// The hopper's sliders and world link are coordinate frames, not drawn; its base is the
/// body; its leg is one capsule from the body to wherever the prismatic joint r put the foot.
#[test]
fn the_hopper_is_drawn_as_a_body_and_a_leg_reaching_its_foot() {
    let (problem, scene) = hopper_scene();
    let model = scene.mechanics.model();
    let names = model.link_names();
    let link = |name: &str| names.iter().position(|n| n == name).unwrap();
    assert_eq!(
        frames_only(model),
        names
            .iter()
            .map(|n| ["world", "slider_x", "slider_z"].contains(&n.as_str()))
            .collect::<Vec<_>>()
    );
    assert_eq!(base_link(model), link("body"));
    for r in [0.3, 0.5, 0.7] {
        let mut motion = motion_of(&problem, 2, 0.05, false);
        for q in &mut motion.q {
            q.copy_from_slice(&[0.2, 0.6, 0.4, r]);
        }
        let drawing = drawing(&scene, std::slice::from_ref(&motion));
        assert!(
            drawing
                .body
                .parts
                .iter()
                .all(|p| p.link == link("body") || p.link == link("foot")),
            "only bodies are drawn"
        );
        let leg: Vec<&Part> = drawing
            .body
            .parts
            .iter()
            .filter(|p| p.slide.is_some())
            .collect();
        assert_eq!(leg.len(), 1);
        let (foot, first) = leg[0].slide.unwrap();
        assert_eq!((leg[0].link, foot), (link("body"), link("foot")));
        // The leg's far end, placed with the foot's pose, is around the foot; its near end
        // around the body: its extent along the leg is r plus a radius at each end.
        let frame = &drawing.frames[0][0];
        let place = |l: usize, v: &[f64; 3]| {
            let (p, q) = frame.links[l];
            let m = rotation_of(&q);
            [0, 1, 2].map(|i| p[i] + (0..3).map(|j| m[i][j] * v[j]).sum::<f64>())
        };
        let (body, foot_at) = (frame.links[link("body")].0, frame.links[link("foot")].0);
        let axis = [0, 1, 2].map(|i| (foot_at[i] - body[i]) / r);
        let along: Vec<f64> = leg[0]
            .vertices
            .iter()
            .enumerate()
            .map(|(i, v)| {
                let w = place(
                    if i as u32 >= first {
                        foot
                    } else {
                        link("body")
                    },
                    v,
                );
                (0..3).map(|j| (w[j] - body[j]) * axis[j]).sum::<f64>()
            })
            .collect();
        let radius = 0.025 * drawing.size;
        let (lo, hi) = along
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
        assert!((lo + radius).abs() < 1e-9, "r = {r}: near end at {lo}");
        assert!((hi - r - radius).abs() < 1e-9, "r = {r}: far end at {hi}");
    }
}

/// The legend says what each kind of result is: a solve's summary names its integrator too,
/// and is still a plan; a relaxed plan and a failed one say NOT SOLVED with the verdict's word
/// (amber and red); a simulation gives its integrator and duration.
#[test]
fn the_legend_names_a_plans_verdict_and_a_simulations_integrator() {
    let solved = serde_json::json!({
        "kind": "plan", "status": "solve_succeeded", "ipopt_status": "solve_succeeded",
        "objective": 6.948567253213889, "integrator": "midpoint", "max_slack": 0.0,
        "slack_tolerance": 1e-4,
    });
    let legend = legend_of(&solved);
    assert_eq!(legend.standing, Standing::Solved);
    assert_eq!(legend.detail, "plan, solve_succeeded, objective 6.948567e0");
    assert_eq!(legend.standing.colour(), None);

    let relaxed = serde_json::json!({
        "kind": "plan", "status": "relaxed_contact", "ipopt_status": "solve_succeeded",
        "objective": 130.25, "integrator": "midpoint", "max_slack": 0.31,
        "slack_tolerance": 1e-4,
    });
    let legend = legend_of(&relaxed);
    assert_eq!(legend.standing, Standing::Relaxed);
    assert_eq!(
        legend.detail,
        "plan, NOT SOLVED: relaxed_contact (slack 3.10e-1 above tolerance 1e-4: the contact \
         model is broken), objective 1.302500e2"
    );
    assert_eq!(legend.standing.colour(), Some("#b35c00"));

    let infeasible = serde_json::json!({
        "status": "infeasible_problem_detected", "ipopt_status": "infeasible_problem_detected",
        "objective": 2.0, "integrator": "galerkin",
    });
    let legend = legend_of(&infeasible);
    assert_eq!(legend.standing, Standing::Unsolved);
    assert_eq!(
        legend.detail,
        "plan, NOT SOLVED: infeasible_problem_detected, objective 2.000000e0"
    );
    assert_eq!(legend.standing.colour(), Some("#c0392b"));

    let timeout = serde_json::json!({
        "status": "timeout", "ipopt_status": "maximum_wall_time_exceeded", "objective": 1.0,
    });
    assert_eq!(legend_of(&timeout).standing, Standing::Unsolved);
    assert!(legend_of(&timeout).detail.contains("NOT SOLVED: timeout"));
    // A status vito never writes is not repeated.
    let odd = serde_json::json!({"status": "<b>fine</b>", "ipopt_status": "x"});
    assert_eq!(legend_of(&odd).detail, "plan, NOT SOLVED: unknown status");

    // Simulations, with `kind` and (older summaries) without.
    for kind in [Some("simulation"), None] {
        let mut sim = serde_json::json!({
            "integrator": "midpoint", "steps": 2000, "duration": 1.0,
            "units": {"length": "m", "time": "s"},
        });
        if let Some(k) = kind {
            sim["kind"] = k.into();
        }
        let legend = legend_of(&sim);
        assert_eq!(legend.standing, Standing::Simulation);
        assert_eq!(legend.detail, "simulation (midpoint), 1 s, 2000 steps");
    }
}

/// The strip's caption names the verdict of the motion it draws, in the legend's colour.
#[test]
fn the_strip_names_the_verdict() {
    let (problem, scene) = hopper_scene();
    let mut motion = motion_of(&problem, 20, 0.05, false);
    motion.standing = Standing::Relaxed;
    motion.detail = "plan, NOT SOLVED: relaxed_contact".into();
    let drawing = drawing(&scene, std::slice::from_ref(&motion));
    for layout in [StripLayout::Panels, StripLayout::World] {
        let svg = strip_svg(&scene, &drawing, &motion, 4, layout);
        assert!(
            svg.contains(
                r##"<text class="verdict" data-standing="relaxed" x="6" y="15" fill="#b35c00">plan, NOT SOLVED: relaxed_contact</text>"##
            ),
            "{layout:?}: {svg}"
        );
        assert_eq!(svg.matches("<g").count(), svg.matches("</g>").count());
    }
}

/// The page's JSON holds no character that could change the HTML parser's state inside the
/// script element, and parses back to the same value.
#[test]
fn script_json_escapes_markup_and_line_separators() {
    let hostile = "<!--<script></script>&amp;\u{2028}\u{2029}]]>\\<";
    let value = json!({ "name": hostile, "list": [hostile, "plain"] });
    let text = script_json(&value);
    for c in ['<', '>', '&', '\u{2028}', '\u{2029}'] {
        assert!(!text.contains(c), "{c:?} in {text}");
    }
    assert_eq!(serde_json::from_str::<Value>(&text).unwrap(), value);
}

/// Every character XML cares about becomes an entity, forbidden controls U+FFFD.
#[test]
fn xml_escape_keeps_any_name_well_formed() {
    assert_eq!(
        xml_escape("a<b>&\"c'\u{1}\u{ffff}]]>"),
        "a&lt;b&gt;&amp;&quot;c&apos;\u{fffd}\u{fffd}]]&gt;"
    );
}

/// Only files vito wrote count as its pages and strips: by the mark at their start (or an
/// older vito page's exact head), not by a mark quoted further on.
#[test]
fn vito_pages_and_strips_are_recognised_by_their_heads() {
    assert!(PAGE_TEMPLATE.starts_with("<!DOCTYPE html>\n"));
    assert!(is_vito_page(PAGE_TEMPLATE.as_bytes()));
    let older = format!(
        "{LEGACY_PAGE_HEAD}<style></style></head><body><pre id=\"vito-status\"></pre></body>"
    );
    assert!(is_vito_page(older.as_bytes()));
    let notes = format!(
        "<!DOCTYPE html>\n<html><body><p>my notes</p>{}<pre id=\"vito-status\"></pre>{PAGE_MARK}</body></html>",
        "x".repeat(MARK_WINDOW)
    );
    assert!(!is_vito_page(notes.as_bytes()));
    assert!(!is_vito_page(b"<p>id=\"vito-status\"</p>"));
    let (problem, scene) = hopper_scene();
    let motion = motion_of(&problem, 5, 0.05, false);
    let drawing = drawing(&scene, std::slice::from_ref(&motion));
    let strip = strip_svg(&scene, &drawing, &motion, 3, StripLayout::Panels);
    assert!(is_vito_strip(strip.as_bytes()));
    assert!(is_vito_strip(
        b"<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"1\">\n<!-- vito strip --><rect />"
    ));
    assert!(!is_vito_strip(b"<svg>\n<!-- mine --><!-- vito strip -->"));
}

/// A hostile title and time unit reach the strip escaped: it parses as XML and holds them as
/// text, with no element they could have opened.
#[test]
fn strip_svg_parses_with_markup_in_names() {
    let (problem, mut scene) = hopper_scene();
    let hostile = "</text><script>alert(1)</script><text>&<![CDATA[x]]>\"'";
    scene.title = hostile.to_owned();
    scene.time_unit = hostile.to_owned();
    let motion = motion_of(&problem, 5, 0.05, false);
    let drawing = drawing(&scene, std::slice::from_ref(&motion));
    let svg = strip_svg(&scene, &drawing, &motion, 3, StripLayout::Panels);
    let doc = roxmltree::Document::parse(&svg).expect("the strip is XML");
    assert!(doc.descendants().all(|n| n.tag_name().name() != "script"));
    let title = doc
        .descendants()
        .find(|n| n.has_tag_name("title"))
        .and_then(|n| n.text())
        .unwrap();
    assert_eq!(title, format!("{hostile}: 3 poses"));
    let labels: Vec<&str> = doc
        .descendants()
        .filter(|n| n.has_tag_name("text") && n.attribute("class") != Some("verdict"))
        .filter_map(|n| n.text())
        .collect();
    assert_eq!(labels.len(), 3);
    assert!(labels.iter().all(|l| l.ends_with(hostile)), "{labels:?}");
    // One world frame: one line of times, holding the unit as text.
    let svg = strip_svg(&scene, &drawing, &motion, 3, StripLayout::World);
    let doc = roxmltree::Document::parse(&svg).expect("the world strip is XML");
    assert!(doc.descendants().all(|n| n.tag_name().name() != "script"));
    let times = doc
        .descendants()
        .find(|n| n.attribute("class") == Some("times"))
        .and_then(|n| n.text())
        .unwrap();
    assert!(
        times.ends_with(&format!("{hostile}, earlier ones lighter")),
        "{times}"
    );
}

/// Each pose group's polygons' mean x in the SVG's pixels, in the strip's order.
fn pose_centres(svg: &str) -> Vec<f64> {
    let doc = roxmltree::Document::parse(svg).expect("the strip is XML");
    doc.descendants()
        .filter(|n| n.attribute("class") == Some("pose"))
        .map(|g| {
            let xs: Vec<f64> = g
                .descendants()
                .filter(|n| n.has_tag_name("polygon"))
                .flat_map(|p| {
                    p.attribute("points")
                        .unwrap()
                        .split(' ')
                        .map(|xy| xy.split(',').next().unwrap().parse::<f64>().unwrap())
                        .collect::<Vec<_>>()
                })
                .collect();
            assert!(!xs.is_empty(), "a pose without polygons");
            xs.iter().sum::<f64>() / xs.len() as f64
        })
        .collect()
}

/// `--world`: the poses of a motion moving forward stand at their true x over one terrain,
/// each further along than the one before, by the base's own advance at the strip's scale;
/// the caption still names the verdict. Side by side (the default), pose i stays in
/// panel i, each over its own terrain.
#[test]
fn the_world_strip_draws_poses_at_their_true_x() {
    let (problem, scene) = hopper_scene();
    let motion = motion_of(&problem, 20, 0.05, false);
    let drawing = drawing(&scene, std::slice::from_ref(&motion));
    let n = 5;
    let world = strip_svg(&scene, &drawing, &motion, n, StripLayout::World);
    assert!(is_vito_strip(world.as_bytes()));
    assert!(world.contains(r#"<text class="verdict" data-standing="solved""#));
    assert_eq!(world.matches("<path").count(), 1, "one terrain");
    assert_eq!(world.matches("<g").count(), world.matches("</g>").count());
    let centres = pose_centres(&world);
    assert_eq!(centres.len(), n);
    assert!(
        centres.windows(2).all(|w| w[1] > w[0]),
        "poses not in order along x: {centres:?}"
    );
    // One scale for the whole strip: each pose's contact point stands at its world x times
    // the same pixels per unit (from the first pose's), so progress is drawn as it happened.
    let frames = strip_frames(&drawing.frames[0], n);
    let foot_x: Vec<f64> = frames.iter().map(|f| f.contacts[0][0]).collect();
    let doc = roxmltree::Document::parse(&world).unwrap();
    let dots: Vec<f64> = doc
        .descendants()
        .filter(|n| n.has_tag_name("circle"))
        .map(|c| c.attribute("cx").unwrap().parse().unwrap())
        .collect();
    assert_eq!(dots.len(), n);
    assert!(foot_x[n - 1] - foot_x[0] > 0.2, "{foot_x:?}");
    let scale = (dots[n - 1] - dots[0]) / (foot_x[n - 1] - foot_x[0]);
    assert!(scale > 50.0, "{scale} px per unit");
    for i in 1..n - 1 {
        let drawn = dots[0] + scale * (foot_x[i] - foot_x[0]);
        assert!(
            (dots[i] - drawn).abs() < 0.2,
            "pose {i}: {} against {drawn}",
            dots[i]
        );
    }
    let panels = strip_svg(&scene, &drawing, &motion, n, StripLayout::Panels);
    assert_eq!(panels.matches("<path").count(), n, "a terrain per pose");
    let doc = roxmltree::Document::parse(&panels).unwrap();
    let width: f64 = doc
        .root_element()
        .attribute("width")
        .unwrap()
        .parse()
        .unwrap();
    for (i, c) in pose_centres(&panels).iter().enumerate() {
        let panel = width / n as f64;
        assert!(
            *c > panel * i as f64 && *c < panel * (i + 1) as f64,
            "pose {i} at {c}, outside its panel of {panel}"
        );
    }
}
