//! The animation page in a real browser: Debian's headless Chromium loads the pages vito
//! writes for the hopper, LittleDog and HAMR, with no console error; screenshots at two
//! knots differ around the robot and match elsewhere; the robot's pixels lie where the
//! model's own kinematics (computed here, in Rust) put its base, projected with the camera
//! the page reports; strip mode draws N robots.
//!
//! Without `chromium` the test is skipped with a message, except under CI (`CI` set), where
//! it fails. `VITO_VIEW_SCREENSHOTS=DIR` keeps the screenshots in DIR.

use std::path::{Path, PathBuf};
use std::process::Command;

use vito::files::trajectory_csv::{RecordedTrajectory, read_trajectory};
use vito::model::link_pose;
use vito::view::{Scene, base_link, scene};

const WIDTH: usize = 900;
const HEIGHT: usize = 600;

fn chromium() -> Option<PathBuf> {
    ["chromium", "chromium-browser"].iter().find_map(|name| {
        let found = Command::new(name).arg("--version").output().ok()?;
        found.status.success().then(|| PathBuf::from(name))
    })
}

/// Longest a Chromium run may take: a page that never finishes loading fails the test
/// instead of stopping the suite.
const BROWSER_DEADLINE: std::time::Duration = std::time::Duration::from_secs(300);

/// Chromium for a test's browser half; None (the half skipped, with a message) where it is
/// not installed, except under CI (`CI` set), where that fails.
fn chromium_for_the_browser_half() -> Option<PathBuf> {
    let found = chromium();
    if found.is_none() {
        assert!(
            std::env::var_os("CI").is_none(),
            "chromium is missing under CI"
        );
        eprintln!("skipped the browser half: chromium is not installed");
    }
    found
}

/// Runs headless Chromium on `url` with `args`; returns (stdout, stderr). A run past
/// [`BROWSER_DEADLINE`] is killed with its process group and fails.
fn browse(browser: &Path, profile: &Path, url: &str, args: &[String]) -> (String, String) {
    use std::os::unix::process::CommandExt;
    let logs = tempfile::tempdir().unwrap();
    let (stdout, stderr) = (logs.path().join("stdout"), logs.path().join("stderr"));
    let mut child = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--no-first-run",
            "--hide-scrollbars",
            "--force-device-scale-factor=1",
            "--enable-logging=stderr",
            "--v=0",
            &format!("--window-size={WIDTH},{HEIGHT}"),
            &format!("--user-data-dir={}", profile.display()),
        ])
        .args(args)
        .arg(url)
        .process_group(0)
        .stdin(std::process::Stdio::null())
        .stdout(std::fs::File::create(&stdout).unwrap())
        .stderr(std::fs::File::create(&stderr).unwrap())
        .spawn()
        .expect("chromium runs");
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > BROWSER_DEADLINE {
            let _ = rustix::process::kill_process_group(
                rustix::process::Pid::from_child(&child),
                rustix::process::Signal::KILL,
            );
            let _ = child.wait();
            panic!("{url}: chromium did not finish within {BROWSER_DEADLINE:?}");
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    let read = |p: &Path| String::from_utf8_lossy(&std::fs::read(p).unwrap()).into_owned();
    (read(&stdout), read(&stderr))
}

/// Console lines (the page logs nothing; an error shows as a console line).
fn console_lines(stderr: &str) -> Vec<&str> {
    stderr.lines().filter(|l| l.contains("CONSOLE")).collect()
}

/// Asserts that Chromium's `stderr` holds no console line (`page` names the page in the
/// message).
fn assert_no_console_lines(stderr: &str, page: &str) {
    let lines = console_lines(stderr);
    assert!(lines.is_empty(), "{page}: {lines:?}");
}

/// The page's status element (JSON) from a DOM dump.
fn status(dom: &str) -> serde_json::Value {
    let start = dom.find("id=\"vito-status\"").expect("status element");
    let text = &dom[start..];
    let text = &text[text.find('>').unwrap() + 1..text.find("</pre>").unwrap()];
    let text = text
        .replace("&quot;", "\"")
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&");
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("status {text}: {e}"))
}

/// The scene data a page written by vito embeds (the JSON its script starts from).
pub fn page_data_of(html: &str) -> serde_json::Value {
    let start = html.find("const D = ").expect("the page's data") + "const D = ".len();
    let end = start + html[start..].find(";\n").expect("the data's end");
    serde_json::from_str(&html[start..end]).expect("the page's data is JSON")
}

/// RGB pixels of a PNG.
struct Image {
    width: usize,
    height: usize,
    rgb: Vec<[u8; 3]>,
}

fn read_png(path: &Path) -> Image {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = info.color_type.samples();
    let rgb = buf[..info.buffer_size()]
        .chunks(channels)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    Image {
        width: info.width as usize,
        height: info.height as usize,
        rgb,
    }
}

/// A robot pixel: the orange of skeleton capsules or the blue-grey of link shapes (the
/// terrain is beige, the background and grid neutral grey).
fn robot_pixel(p: [u8; 3]) -> bool {
    let (r, g, b) = (i32::from(p[0]), i32::from(p[1]), i32::from(p[2]));
    (r - b > 60 && g < r) || (b - r > 12 && b - g > 4)
}

/// Projects a world point with the camera the page reports.
fn project(camera: &serde_json::Value, p: [f64; 3]) -> [f64; 2] {
    let v = |k: &str| -> [f64; 3] {
        let a = camera[k].as_array().unwrap();
        [0, 1, 2].map(|i| a[i].as_f64().unwrap())
    };
    let (eye, right, up, fwd) = (v("eye"), v("right"), v("up"), v("fwd"));
    let d = [p[0] - eye[0], p[1] - eye[1], p[2] - eye[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let f = camera["f"].as_f64().unwrap();
    let (w, h) = (camera["w"].as_f64().unwrap(), camera["h"].as_f64().unwrap());
    let z = dot(d, fwd);
    [
        w / 2.0 + f * dot(d, right) / z,
        h / 2.0 - f * dot(d, up) / z,
    ]
}

/// `vito view DIR --out <temporary>/animation.html` from the repository root: the page's
/// path and the directory holding it (removed when dropped).
fn write_page(root: &Path, dir: &str) -> (tempfile::TempDir, std::path::PathBuf) {
    let tmp = tempfile::tempdir().unwrap();
    let page = tmp.path().join("animation.html");
    let run = Command::new(env!("CARGO_BIN_EXE_vito"))
        .current_dir(root)
        .args(["view", dir, "--out"])
        .arg(&page)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    (tmp, page)
}

/// The scene of the problem the result directory `dir` (under `root`) was solved from (its
/// summary's `problem_file`), and its trajectory as recorded.
fn solved(root: &Path, dir: &str) -> (Scene, RecordedTrajectory) {
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root.join(dir).join("summary.json")).unwrap(),
    )
    .unwrap();
    let problem =
        vito::problem::load(&root.join(summary["problem_file"].as_str().unwrap()), &[]).unwrap();
    let scene = scene(&problem).unwrap();
    let csv = std::fs::read_to_string(root.join(dir).join("trajectory.csv")).unwrap();
    let recorded = read_trajectory(&csv, &problem.robot.coordinates, &[]).unwrap();
    (scene, recorded)
}

/// Checks one result directory's page.
fn check(browser: &Path, dir: &str, knots: [usize; 2], keep: Option<&Path>) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let (tmp, page) = write_page(root, dir);
    let html = std::fs::read_to_string(&page).unwrap();
    assert!(
        html.len() < 2_000_000,
        "{dir}: page of {} bytes",
        html.len()
    );

    // The model's kinematics, here: the base (its first link that is a body, not a frame
    // such as the world or a planar base's slider) and every link at the two knots.
    let (scene, recorded) = solved(root, dir);
    let model = scene.mechanics.model();
    let links = |k: usize| -> Vec<[f64; 3]> {
        model
            .link_names()
            .iter()
            .map(|name| link_pose(model, model.link_index(name).unwrap(), &recorded.q[k]).1)
            .collect()
    };
    let base_index = base_link(model);
    let base = |k: usize| links(k)[base_index];

    let url =
        |fragment: &str| format!("file://{}#size={WIDTH}x{HEIGHT}&{fragment}", page.display());
    let profile = tmp.path().join("profile");
    let mut shots = Vec::new();
    let mut camera = serde_json::Value::Null;
    for (i, &k) in knots.iter().enumerate() {
        let t = recorded.times[k];
        let (dom, stderr) = browse(
            browser,
            &profile,
            &url(&format!("t={t}")),
            &["--dump-dom".into()],
        );
        assert_no_console_lines(&stderr, dir);
        let s = status(&dom);
        assert_eq!(s["errors"], serde_json::json!([]), "{dir}");
        assert_eq!(s["ready"], true, "{dir}");
        assert!(
            (s["t"].as_f64().unwrap() - t).abs() <= 1e-9 * t.abs().max(1.0),
            "{dir}"
        );
        camera = s["camera"].clone();
        let shot = tmp.path().join(format!("t{i}.png"));
        let (_, stderr) = browse(
            browser,
            &profile,
            &url(&format!("t={t}")),
            &[format!("--screenshot={}", shot.display())],
        );
        assert_no_console_lines(&stderr, dir);
        shots.push((k, read_png(&shot), shot));
    }
    let (a, b) = (&shots[0].1, &shots[1].1);
    assert_eq!((a.width, a.height), (WIDTH, HEIGHT));

    // Robot pixels around the projected base, at both knots.
    for (k, image, _) in &shots {
        let base = project(&camera, base(*k));
        let mut near = 0;
        for y in (base[1] as i64 - 25).max(0)..(base[1] as i64 + 25).min(HEIGHT as i64) {
            for x in (base[0] as i64 - 25).max(0)..(base[0] as i64 + 25).min(WIDTH as i64) {
                near += usize::from(robot_pixel(image.rgb[y as usize * WIDTH + x as usize]));
            }
        }
        assert!(
            near >= 40,
            "{dir} knot {k}: {near} robot pixels within 25 px of the base at {base:?}"
        );
    }
    // Differs where the robot moved, matches where it did not (legend, bar and the robot's
    // surroundings at both knots left out).
    let mut boxes = Vec::new();
    // Each link's origin, points along each joint's segment from its parent (a long leg
    // between two link origins is robot too) and the contact points.
    let parent_of: Vec<Option<usize>> = model
        .link_names()
        .iter()
        .map(|name| {
            model
                .link_geometry()
                .iter()
                .position(|g| g.children.iter().any(|c| c.link == *name))
        })
        .collect();
    for (k, _, _) in &shots {
        let at = links(*k);
        let along = parent_of.iter().enumerate().flat_map(|(l, p)| {
            let (a, b) = (at[l], p.map_or(at[l], |p| at[p]));
            [0.25, 0.5, 0.75].map(|s| [0, 1, 2].map(|i| a[i] + s * (b[i] - a[i])))
        });
        for p in at
            .iter()
            .copied()
            .chain(along)
            .chain(scene_contacts(&scene, &recorded.q[*k]))
        {
            let s = project(&camera, p);
            boxes.push([s[0] - 70.0, s[1] - 70.0, s[0] + 70.0, s[1] + 70.0]);
        }
    }
    let base_a = project(&camera, base(shots[0].0));
    let (mut changed_near, mut same_far, mut far) = (0, 0, 0);
    for y in 0..HEIGHT {
        for x in 0..WIDTH {
            let i = y * WIDTH + x;
            let (fx, fy) = (x as f64, y as f64);
            if (fx - base_a[0]).abs() < 25.0 && (fy - base_a[1]).abs() < 25.0 {
                changed_near += usize::from(robot_pixel(a.rgb[i]) && !robot_pixel(b.rgb[i]));
            }
            let ui = y > HEIGHT - 80 || (x < 450 && y < 200) || (x > 440 && y < 35);
            let robot = boxes
                .iter()
                .any(|r| fx > r[0] && fx < r[2] && fy > r[1] && fy < r[3]);
            if !ui && !robot {
                far += 1;
                same_far += usize::from(a.rgb[i] == b.rgb[i]);
            }
        }
    }
    assert!(
        changed_near > 200,
        "{dir}: only {changed_near} pixels changed around the base"
    );
    assert!(far > 50_000, "{dir}: {far}");
    assert!(
        same_far as f64 >= 0.999 * far as f64,
        "{dir}: {same_far} of {far} unchanged away from the robot"
    );

    // Strip mode: N robots, side by side (N clusters of robot columns).
    let n = 5;
    let (dom, stderr) = browse(
        browser,
        &profile,
        &url(&format!("strip={n}")),
        &["--dump-dom".into()],
    );
    assert_no_console_lines(&stderr, dir);
    let strip_status = status(&dom);
    assert_eq!(strip_status["copies"], n, "{dir}");
    // The legend's box (its text and contact swatches are not robots).
    let legend: Vec<f64> = strip_status["legend_box"]
        .as_array()
        .expect("the legend's box")
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let in_legend = |x: usize, y: usize| {
        let (x, y) = (x as f64, y as f64);
        x >= legend[0] - 1.0 && x <= legend[2] + 1.0 && y >= legend[1] - 1.0 && y <= legend[3] + 1.0
    };
    let strip = tmp.path().join("strip.png");
    browse(
        browser,
        &profile,
        &url(&format!("strip={n}")),
        &[format!("--screenshot={}", strip.display())],
    );
    let image = read_png(&strip);
    let columns: Vec<bool> = (0..WIDTH)
        .map(|x| {
            (200..HEIGHT - 80)
                .filter(|&y| !in_legend(x, y) && robot_pixel(image.rgb[y * WIDTH + x]))
                .count()
                > 2
        })
        .collect();
    let clusters = columns.windows(2).filter(|w| w[1] && !w[0]).count() + usize::from(columns[0]);
    assert_eq!(clusters, n, "{dir}: {clusters} robots in the strip");

    if let Some(keep) = keep {
        let name = Path::new(dir)
            .iter()
            .rev()
            .nth(usize::from(dir.ends_with("solve")))
            .unwrap();
        let name = name.to_string_lossy();
        std::fs::create_dir_all(keep).unwrap();
        for (i, (_, _, shot)) in shots.iter().enumerate() {
            std::fs::copy(shot, keep.join(format!("{name}_t{i}.png"))).unwrap();
        }
        std::fs::copy(&strip, keep.join(format!("{name}_strip.png"))).unwrap();
    }
}

fn scene_contacts(scene: &vito::view::Scene, q: &[f64]) -> Vec<[f64; 3]> {
    use vito::discrete::Mechanics;
    (0..scene.mechanics.num_contacts())
        .map(|c| scene.mechanics.contact_position(c, q))
        .collect()
}

#[test]
fn pages_load_move_and_strip_in_headless_chromium() {
    let Some(browser) = chromium() else {
        assert!(
            std::env::var_os("CI").is_none(),
            "chromium is missing under CI: vendor-config/install-deps.sh installs it"
        );
        eprintln!(
            "skipped: chromium is not installed (bash vendor-config/install-deps.sh installs it)"
        );
        return;
    };
    let keep = std::env::var_os("VITO_VIEW_SCREENSHOTS").map(PathBuf::from);
    let cases: [(&str, [usize; 2]); 3] = [
        ("results/motion/hopper_2d", [0, 20]),
        ("results/motion/littledog_step", [0, 25]),
        ("results/hamr_jump/solve", [0, 30]),
    ];
    std::thread::scope(|s| {
        for (dir, knots) in cases {
            let (browser, keep) = (&browser, keep.as_deref());
            s.spawn(move || check(browser, dir, knots, keep));
        }
    });
}

/// The pages, strips and sweep plots committed under results/ (listed in results/pages.txt,
/// redrawn by `make pages`) are byte for byte what this build's viewer draws from the
/// committed trajectories: they cannot drift from the viewer.
#[test]
fn committed_pages_are_what_the_viewer_draws() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let list = std::fs::read_to_string(root.join("results/pages.txt")).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let vito = |args: &[&str], codes: &[i32]| {
        let run = Command::new(env!("CARGO_BIN_EXE_vito"))
            .current_dir(root)
            .args(args)
            .output()
            .unwrap();
        assert!(
            run.status.code().is_some_and(|c| codes.contains(&c)),
            "vito {args:?}: {}",
            String::from_utf8_lossy(&run.stderr)
        );
    };
    let mut checked = 0;
    for (i, line) in list
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .enumerate()
    {
        let words: Vec<&str> = line.split_whitespace().collect();
        let fresh = tmp.path().join(format!("{i}"));
        let (drawn, committed) = match words[..] {
            ["page", dir] => {
                let out = fresh.with_extension("html");
                vito(&["view", dir, "--out", out.to_str().unwrap()], &[0]);
                (out, root.join(dir).join("animation.html"))
            }
            ["strip", n, dir, svg, ref problem @ ..] => {
                let out = fresh.with_extension("svg");
                let mut args = vec!["view", dir, "--strip", n, "--svg", out.to_str().unwrap()];
                if let [problem] = problem {
                    args.extend(["--problem", problem]);
                }
                vito(&args, &[0]);
                (out, root.join(svg))
            }
            ["report", dir, metric] => {
                std::fs::create_dir(&fresh).unwrap();
                std::fs::copy(root.join(dir).join("sweep.json"), fresh.join("sweep.json")).unwrap();
                vito(
                    &[
                        "sweep",
                        "report",
                        fresh.to_str().unwrap(),
                        "--metric",
                        metric,
                    ],
                    &[0, 1],
                );
                let name = format!("sweep-{metric}.svg");
                (fresh.join(&name), root.join(dir).join(&name))
            }
            _ => panic!("results/pages.txt: cannot read `{line}`"),
        };
        let (drawn_text, committed_text) = (
            std::fs::read_to_string(&drawn).unwrap(),
            std::fs::read_to_string(&committed).unwrap(),
        );
        assert!(
            drawn_text == committed_text,
            "{} is not what this build draws; run `make pages`",
            committed.display()
        );
        checked += 1;
    }
    assert_eq!(checked, 15);
}

/// Markup in every name that reaches a page or a strip: the problem's name, a URDF link, a
/// joint (a coordinate and input), the collision (the contact, with a comma), the result
/// directory and the summary's `integrator`. `vito simulate` writes the result, `vito view`
/// a page and a strip of it, `vito check --at` reads its CSV back. In headless Chromium the
/// page starts (status ready, no error) and no injected script runs (it would log to the
/// console); the strip parses as XML with no `script` element and loads with no console line.
#[test]
fn markup_in_names_neither_stops_the_page_nor_runs() {
    // One payload per place: an HTML comment opening a script (the "double escaped" state),
    // a closing tag, an injected script that would log, an entity, CDATA (U+2028/2029, which
    // problem and URDF names refuse as invisible, in the summary's integrator).
    let payload = |tag: &str| {
        format!(
            "{tag}<!--<script></script><script>console.log('INJECTED {tag}')</script>&amp;<![CDATA[x]]>'\""
        )
    };
    let xml = |s: &str| {
        s.replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;")
            .replace('"', "&quot;")
    };
    let toml_str = |s: &str| serde_json::to_string(s).unwrap();
    let t = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    std::fs::create_dir(t.path().join("robots")).unwrap();
    let (link, joint, contact) = (payload("link"), payload("joint,j"), payload("left,foot"));
    // A problem's name names its output directory: no `/` (so no closing tag).
    let name = payload("problem").replace('/', "");
    let urdf = std::fs::read_to_string(root.join("problems/robots/hopper_2d.urdf"))
        .unwrap()
        .replace("\"body\"", &format!("\"{}\"", xml(&link)))
        .replace("\"theta\"", &format!("\"{}\"", xml(&joint)))
        .replace("\"foot_contact\"", &format!("\"{}\"", xml(&contact)));
    std::fs::write(t.path().join("robots/hopper_2d.urdf"), urdf).unwrap();
    let problem = std::fs::read_to_string(root.join("problems/hopper_2d.toml"))
        .unwrap()
        .replace(
            "name = \"hopper-2d\"",
            &format!("name = {}", toml_str(&name)),
        )
        .replace("theta = 0.0,", &format!("{} = 0.0,", toml_str(&joint)))
        .replace("theta = [-10.0", &format!("{} = [-10.0", toml_str(&joint)))
        .replace("theta = 0.1,", &format!("{} = 0.1,", toml_str(&joint)));
    std::fs::write(t.path().join("p.toml"), problem).unwrap();
    let vito = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_vito"))
            .current_dir(t.path())
            .args(args)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert_eq!(out.status.code(), Some(0), "{args:?}: {stderr}");
    };
    let dir = payload("dir").replace('/', "");
    vito(&[
        "simulate",
        "p.toml",
        "--duration",
        "1.0",
        "--out",
        &dir,
        "--quiet",
    ]);
    // vito's own CSV, its contact holding a comma, reads back.
    let csv = std::fs::read_to_string(t.path().join(&dir).join("trajectory.csv")).unwrap();
    assert!(csv.contains("left,foot"), "{}", &csv[..200.min(csv.len())]);
    vito(&[
        "check",
        "p.toml",
        "--derivatives",
        "--at",
        &format!("{dir}/trajectory.csv"),
    ]);
    // A hostile integrator name in the summary.
    let summary_path = t.path().join(&dir).join("summary.json");
    let mut summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&summary_path).unwrap()).unwrap();
    summary["integrator"] = format!("{}\u{2028}\u{2029}", payload("integrator")).into();
    std::fs::write(&summary_path, summary.to_string()).unwrap();
    vito(&[
        "view",
        &dir,
        "--out",
        "page.html",
        "--strip",
        "3",
        "--svg",
        "strip.svg",
    ]);

    let svg = std::fs::read_to_string(t.path().join("strip.svg")).unwrap();
    let doc = roxmltree::Document::parse(&svg).expect("the strip parses as XML");
    assert!(doc.descendants().all(|n| !n.has_tag_name("script")));
    let title = doc.descendants().find(|n| n.has_tag_name("title")).unwrap();
    assert_eq!(title.text(), Some(format!("{name}: 3 poses").as_str()));

    let Some(browser) = chromium_for_the_browser_half() else {
        return;
    };
    let profile = t.path().join("profile");
    let page = t.path().join("page.html");
    let (dom, stderr) = browse(
        &browser,
        &profile,
        &format!("file://{}#size={WIDTH}x{HEIGHT}", page.display()),
        &["--dump-dom".into()],
    );
    assert_no_console_lines(&stderr, "page.html");
    assert!(!stderr.contains("INJECTED"), "{stderr}");
    let s = status(&dom);
    assert_eq!(s["errors"], serde_json::json!([]));
    assert_eq!(s["ready"], true);
    // The legend shows the names as text.
    assert!(
        dom.contains("INJECTED dir"),
        "the directory's name is not shown"
    );
    let (_, stderr) = browse(
        &browser,
        &profile,
        &format!("file://{}", t.path().join("strip.svg").display()),
        &["--dump-dom".into()],
    );
    assert_no_console_lines(&stderr, "strip.svg");
    assert!(!stderr.contains("INJECTED"), "{stderr}");
}

/// Whether any pixel within one of `p` differs between two screenshots.
fn differs_near(a: &Image, b: &Image, p: [f64; 2]) -> bool {
    let (x, y) = (p[0].round() as i64, p[1].round() as i64);
    (-1..=1).any(|dy| {
        (-1..=1).any(|dx| {
            let (x, y) = (x + dx, y + dy);
            x >= 0
                && y >= 0
                && (x as usize) < a.width
                && (y as usize) < a.height
                && a.rgb[y as usize * a.width + x as usize]
                    != b.rgb[y as usize * b.width + x as usize]
        })
    })
}

/// Distance from `p` to the segment from `a` to `b` (screen pixels).
fn to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let s = if len2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((p[0] - a[0] - s * dx).powi(2) + (p[1] - a[1] - s * dy).powi(2)).sqrt()
}

/// LittleDog climbing the step. Drop lines (on by default): at the knot where a foot stands
/// highest above the terrain under it, the pixels between the foot and the terrain
/// (H(x, y) from the problem's terrain, computed here) differ from the page with `drops=0`,
/// and those below the terrain do not: the line ends on the terrain. Foot trails (`trails=1`, off by default): halfway through, the
/// contact points of earlier knots are drawn, and those of later knots (away from every
/// earlier path) are not.
#[test]
fn drop_lines_reach_the_terrain_and_trails_follow_the_feet() {
    let Some(browser) = chromium() else {
        assert!(
            std::env::var_os("CI").is_none(),
            "chromium is missing under CI"
        );
        eprintln!("skipped: chromium is not installed");
        return;
    };
    let dir = "results/motion/littledog_step";
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let (tmp, page) = write_page(root, dir);
    let (scene, recorded) = solved(root, dir);
    let contacts: Vec<Vec<[f64; 3]>> = recorded
        .q
        .iter()
        .map(|q| scene_contacts(&scene, q))
        .collect();
    // The foot highest above the terrain under it (H(x, y) computed here).
    let gap = |(k, c): (usize, usize)| {
        let p = contacts[k][c];
        p[2] - scene.terrain.height_at(p[0], p[1])
    };
    let (k, c) = (0..contacts.len())
        .flat_map(|k| (0..contacts[k].len()).map(move |c| (k, c)))
        .max_by(|a, b| gap(*a).total_cmp(&gap(*b)))
        .expect("a foot");
    let foot = contacts[k][c];
    let ground = [foot[0], foot[1], scene.terrain.height_at(foot[0], foot[1])];
    assert!(foot[2] - ground[2] > 0.05, "foot {foot:?} over {ground:?}");

    let profile = tmp.path().join("profile");
    let url =
        |fragment: &str| format!("file://{}#size={WIDTH}x{HEIGHT}&{fragment}", page.display());
    let shot = |fragment: &str, name: &str| {
        let path = tmp.path().join(name);
        let (_, stderr) = browse(
            &browser,
            &profile,
            &url(fragment),
            &[format!("--screenshot={}", path.display())],
        );
        assert_no_console_lines(&stderr, name);
        read_png(&path)
    };
    let t = recorded.times[k];
    let (dom, _) = browse(
        &browser,
        &profile,
        &url(&format!("t={t}")),
        &["--dump-dom".into()],
    );
    let s = status(&dom);
    assert_eq!(s["errors"], serde_json::json!([]));
    assert_eq!(
        s["drops"][0].as_array().map(Vec::len),
        Some(contacts[k].len())
    );
    assert_eq!(
        s["trails"],
        serde_json::json!([]),
        "trails are off by default"
    );
    let camera = s["camera"].clone();
    let (on, off) = (
        shot(&format!("t={t}"), "drops.png"),
        shot(&format!("t={t}&drops=0"), "nodrops.png"),
    );
    let along = |from: [f64; 3], to: [f64; 3], s: f64| {
        project(&camera, [0, 1, 2].map(|i| from[i] + s * (to[i] - from[i])))
    };
    let samples = 20;
    let drawn = (0..samples)
        .filter(|&i| {
            let s = 0.2 + 0.6 * i as f64 / (samples - 1) as f64;
            differs_near(&on, &off, along(foot, ground, s))
        })
        .count();
    assert!(
        drawn >= samples * 3 / 5,
        "{drawn} of {samples} points of the drop line drawn"
    );
    // Below the terrain under the foot: 5 cm further down.
    let floor = [foot[0], foot[1], ground[2] - 0.05];
    let below = (0..samples)
        .filter(|&i| {
            let s = 0.3 + 0.6 * i as f64 / (samples - 1) as f64;
            differs_near(&on, &off, along(ground, floor, s))
        })
        .count();
    assert!(
        below <= 1,
        "{below} of {samples} points below the terrain under the foot drawn"
    );

    // Trails halfway through.
    let mid = contacts.len() / 2;
    let t = recorded.times[mid];
    let (dom, _) = browse(
        &browser,
        &profile,
        &url(&format!("t={t}&trails=1")),
        &["--dump-dom".into()],
    );
    let s = status(&dom);
    assert!(s["trails"][0].as_u64().unwrap() as usize >= (mid + 1) * contacts[0].len());
    let (on, off) = (
        shot(&format!("t={t}&trails=1"), "trails.png"),
        shot(&format!("t={t}"), "notrails.png"),
    );
    let screen: Vec<Vec<[f64; 2]>> = contacts
        .iter()
        .map(|row| row.iter().map(|p| project(&camera, *p)).collect())
        .collect();
    let earlier: Vec<[f64; 2]> = (1..mid - 1).flat_map(|j| screen[j].clone()).collect();
    let shown = earlier
        .iter()
        .filter(|p| differs_near(&on, &off, **p))
        .count();
    assert!(
        shown * 2 >= earlier.len(),
        "{shown} of {} earlier contact points on a trail",
        earlier.len()
    );
    let away: Vec<[f64; 2]> = (mid + 2..screen.len())
        .flat_map(|j| screen[j].clone())
        .filter(|p| {
            (0..screen[0].len())
                .all(|c| (0..mid).all(|j| to_segment(*p, screen[j][c], screen[j + 1][c]) > 8.0))
        })
        .collect();
    assert!(
        away.len() >= 4,
        "{} later points away from the trails",
        away.len()
    );
    let later = away.iter().filter(|p| differs_near(&on, &off, **p)).count();
    assert_eq!(
        later,
        0,
        "{later} of {} later contact points drawn",
        away.len()
    );
}

/// The brick's simulation moved to the edge of what `vito view` draws: from its first pose
/// at the origin, every later pose at ±0.99 of the largest distance accepted (10,000 robot
/// sizes) along x and y, so that the page's terrain and grid span the widest range there is.
/// The page loads in headless Chromium (status ready, no error); 1.01 of the distance is
/// refused (exit 2).
#[test]
fn a_page_at_the_edge_of_the_drawable_range_loads() {
    let t = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let problem_file = root.join("problems/brick_3d.toml");
    let vito = |args: &[&std::ffi::OsStr]| {
        let out = Command::new(env!("CARGO_BIN_EXE_vito"))
            .current_dir(t.path())
            .args(args)
            .output()
            .unwrap();
        (
            out.status.code(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    let os = |s: &str| std::ffi::OsString::from(s);
    let (code, stderr) = vito(&[
        &os("simulate"),
        problem_file.as_os_str(),
        &os("--duration"),
        &os("0.5"),
        &os("--out"),
        &os("r"),
        &os("--quiet"),
    ]);
    assert_eq!(code, Some(0), "{stderr}");
    // The largest distance accepted, from the library's own measure of the brick.
    let problem = vito::problem::load(&problem_file, &[]).unwrap();
    let scene = scene(&problem).unwrap();
    let csv = std::fs::read_to_string(t.path().join("r/trajectory.csv")).unwrap();
    let recorded = read_trajectory(&csv, &problem.robot.coordinates, &[]).unwrap();
    let motion = vito::view::Motion {
        name: "r".into(),
        detail: String::new(),
        standing: vito::view::Standing::Simulation,
        times: recorded.times.clone(),
        q: recorded.q.clone(),
        normal: Vec::new(),
        friction: Vec::new(),
    };
    let drawing = vito::view::drawing(&scene, std::slice::from_ref(&motion));
    let far = vito::view::MAX_DISTANCE_IN_SIZES * vito::view::robot_size(&scene, &drawing);
    assert!((far - 2291.0).abs() < 1.0, "the brick's diagonal: {far}");
    let moved = |name: &str, reach: f64| {
        let dir = t.path().join(name);
        std::fs::create_dir(&dir).unwrap();
        std::fs::copy(t.path().join("r/summary.json"), dir.join("summary.json")).unwrap();
        let mut lines: Vec<String> = csv.lines().map(str::to_owned).collect();
        for (k, line) in lines.iter_mut().enumerate().skip(2) {
            let mut cells: Vec<String> = line.split(',').map(str::to_owned).collect();
            let side = if k % 2 == 0 { 1.0 } else { -1.0 };
            cells[1] = format!("{}", side * reach * far);
            cells[2] = format!("{}", -side * reach * far);
            *line = cells.join(",");
        }
        std::fs::write(dir.join("trajectory.csv"), lines.join("\n") + "\n").unwrap();
        let page = dir.join("page.html");
        let (code, stderr) = vito(&[
            &os("view"),
            &os(name),
            &os("--problem"),
            problem_file.as_os_str(),
            &os("--out"),
            page.as_os_str(),
        ]);
        (code, stderr, page)
    };
    let (code, stderr, _) = moved("beyond", 1.01);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("column `base_x`"), "{stderr}");
    let (code, stderr, page) = moved("edge", 0.99);
    assert_eq!(code, Some(0), "{stderr}");
    let data = page_data_of(&std::fs::read_to_string(&page).unwrap());
    let terrain_x = data["terrain"]["x"].as_array().unwrap();
    let span = terrain_x.last().unwrap().as_f64().unwrap() - terrain_x[0].as_f64().unwrap();
    assert!(span > 1.9 * far, "the terrain spans {span}");

    let Some(browser) = chromium_for_the_browser_half() else {
        return;
    };
    let (dom, stderr) = browse(
        &browser,
        &t.path().join("profile"),
        &format!("file://{}#size={WIDTH}x{HEIGHT}", page.display()),
        &["--dump-dom".into()],
    );
    assert_no_console_lines(&stderr, "page.html");
    let s = status(&dom);
    assert_eq!(s["errors"], serde_json::json!([]));
    assert_eq!(s["ready"], true);
}
