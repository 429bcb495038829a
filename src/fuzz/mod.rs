//! The fuzz harness: generated and mutated inputs fed in memory to the library calls the
//! commands make on what a user gives, each input of a named [`Kind`]:
//!
//! - `problem`, `urdf`: the project's own problem files and URDFs mutated by a seeded mutator
//!   (byte changes, token swaps, numbers replaced by NaN, ±inf, 1e308, −0 or huge integers,
//!   lines deleted or repeated, deep nesting, hostile snippets), through problem loading
//!   ([`crate::problem::load_from_str`], parsing and every validation check, the URDF
//!   included) and URDF loading ([`crate::model::Model::from_urdf_str`]); each `problem`
//!   input also carries `--starts` and `--jobs` counts at and past their limits ([`COUNTS`]),
//!   through the commands' count check (accepted exactly within the limits, else a panic);
//! - `expression`: deep expressions (up to 50,000 nested parentheses, unary minus or
//!   functions) in numeric fields, in the file and through `--set`, `--set` key paths of up
//!   to 20,000 parts, and TOML arrays, inline tables, table headers and dotted keys nested
//!   up to 100,000 deep, through problem loading;
//! - `chain`: generated URDFs around and beyond the documented limits: serial chains, trees,
//!   fixed-joint chains and stars, mimic chains, chains with contacts and transmissions, and
//!   loop joints, of up to 10,001 links;
//! - `attributes`: up to 200,000 attributes on one element, and up to 200,000 elements
//!   (visuals, materials, transmissions, loop joints, unknown elements, links, comments),
//!   in a robot of the project;
//! - `csv`: trajectory CSVs written for the project's problems, mutated (cells made NaN,
//!   ±inf, huge or empty, headers renamed or duplicated, columns added, removed or
//!   repeated, ragged rows, rows repeated up to 100,000 times, times scaled, other files'
//!   text), through the readers of a warm start (`initial_guess.warm_start`), of
//!   `vito simulate --inputs`/`--track` (and the input policy they make) and of
//!   `vito check --at`;
//! - `names`: generated names (markup, comment and CDATA openers, entities, quotes, commas,
//!   brackets, U+2028/U+2029, controls, noncharacters, random code points; up to 70,000
//!   characters) through what writes names into files: the page's script JSON
//!   ([`crate::view::script_json`]: no `<`, `>`, `&`, U+2028, U+2029 left, the same value read
//!   back), a strip's XML text and attributes ([`crate::files::names::xml_escape`]: the document
//!   parses and holds the name), and a trajectory CSV's header (a coordinate and a contact so
//!   named, written by [`crate::files::trajectory_csv::write_trajectory`] and read back by
//!   name). A broken property is a panic.
//!
//! An input must end in `Ok` or an error: a panic is caught and counted, an input taking
//! more than [`HANG`] of the process's CPU time is counted as a hang (CPU time, so that a
//! busy machine does not make a cheap input look like one; a watchdog names an input still
//! running after [`HANG`] of wall time), and an abort or stack overflow ends the run, whose last progress line names
//! the input to repeat from. `examples/fuzz.rs` runs it (`make fuzz`); a short run is in the
//! test suite.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crate::model::{BaseType, Model};
use crate::random::SeededRng;

mod generate;
mod mutate;

use generate::generate;
pub use mutate::mutate;

/// A valid input to mutate: a problem file with its robot's URDF, or a URDF alone.
#[derive(Debug, Clone)]
pub struct Seed {
    /// Where it came from (for messages).
    pub name: String,
    /// The problem file's text (`None` for a URDF alone).
    pub problem: Option<String>,
    /// The URDF's text.
    pub urdf: String,
}

/// The seeds of a checkout: every `*.toml` problem in `problems/` (golden records skipped)
/// with the URDF its `robot.urdf` names, and every `*.urdf` under `problems/robots/`.
pub fn seeds(problems: &Path) -> std::io::Result<Vec<Seed>> {
    let mut out = Vec::new();
    let mut entries: Vec<PathBuf> = std::fs::read_dir(problems)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .collect();
    entries.sort();
    for path in &entries {
        if path.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let text = std::fs::read_to_string(path)?;
        let Some(urdf) = text
            .parse::<toml::Table>()
            .ok()
            .and_then(|t| t.get("robot")?.get("urdf")?.as_str().map(str::to_owned))
        else {
            continue;
        };
        out.push(Seed {
            name: path.display().to_string(),
            problem: Some(text),
            urdf: std::fs::read_to_string(problems.join(urdf))?,
        });
    }
    let mut stack = vec![problems.join("robots")];
    let mut urdfs = Vec::new();
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir)? {
            let path = entry?.path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "urdf") {
                urdfs.push(path);
            }
        }
    }
    urdfs.sort();
    for path in urdfs {
        out.push(Seed {
            name: path.display().to_string(),
            problem: None,
            urdf: std::fs::read_to_string(&path)?,
        });
    }
    Ok(out)
}

/// The CPU time this process has used (all its threads).
fn process_cpu_time() -> Duration {
    let t = rustix::time::clock_gettime(rustix::time::ClockId::ProcessCPUTime);
    Duration::new(
        u64::try_from(t.tv_sec).unwrap_or(0),
        u32::try_from(t.tv_nsec).unwrap_or(0),
    )
}

/// An input taking more CPU time than this is a hang.
pub const HANG: Duration = Duration::from_secs(10);

/// The counts a command line gives (`vito solve`'s and `vito sweep`'s `--starts` and `--jobs`)
/// with the limit the commands check each against before anything is allocated for it.
pub const COUNTS: [(&str, usize); 2] = [
    ("--starts", crate::transcription::MAX_STARTS),
    ("--jobs", crate::sweep::MAX_JOBS),
];

/// Checks `counts` as the commands do ([`crate::files::input::checked_count`]); panics (a
/// finding) when a count is accepted past its limit or refused within it.
fn check_counts(counts: &[(&str, usize)]) {
    for &(option, value) in counts {
        let max = COUNTS.iter().find(|(o, _)| *o == option).map_or(0, |c| c.1);
        let accepted = crate::files::input::checked_count(value, max).is_ok();
        assert_eq!(
            accepted,
            (1..=max).contains(&value),
            "{option} {value} (limit {max})"
        );
    }
}

/// What an input is made of and which library calls it goes through.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Kind {
    /// A mutated problem file (and maybe its URDF), through problem loading.
    Problem,
    /// A mutated URDF alone, through URDF loading.
    Urdf,
    /// Deep expressions, key paths and TOML nesting, through problem loading.
    Expression,
    /// Generated chains, trees and stars of links, through URDF loading.
    Chain,
    /// Many attributes on one element, or many elements, through URDF loading.
    Attributes,
    /// A mutated trajectory CSV, through a command's CSV reader.
    Csv,
    /// A generated name, through the page's JSON, a strip's XML and a CSV header.
    Names,
}

impl Kind {
    /// Every kind, in the order reports list them.
    pub const ALL: [Kind; 7] = [
        Kind::Problem,
        Kind::Urdf,
        Kind::Expression,
        Kind::Chain,
        Kind::Attributes,
        Kind::Csv,
        Kind::Names,
    ];

    /// The kind's name in reports.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Problem => "problem",
            Kind::Urdf => "urdf",
            Kind::Expression => "expression",
            Kind::Chain => "chain",
            Kind::Attributes => "attributes",
            Kind::Csv => "csv",
            Kind::Names => "names",
        }
    }
}

/// Which command's trajectory CSV reader a `csv` input goes through.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CsvReader {
    /// `initial_guess.warm_start` ([`crate::problem::warm_start_from_text`]).
    WarmStart,
    /// `vito simulate --inputs` ([`crate::pipeline::simulation::recorded_inputs`], then the replay policy).
    Inputs,
    /// `vito simulate --track` (the same reader, then the PD tracking policy).
    Track,
    /// `vito check --at` ([`crate::pipeline::trajectory_point::point_from_trajectory`]).
    At,
}

/// One input: what it holds, where it came from.
#[derive(Debug, Clone)]
pub struct Input {
    /// Its kind.
    pub kind: Kind,
    /// Its number in the run (0-based).
    pub index: u64,
    /// The seed it was made from (for messages).
    pub seed: String,
    /// A problem file's text, loaded with `urdf` as its robot.
    pub problem: Option<String>,
    /// A URDF's text.
    pub urdf: String,
    /// `--set` arguments, for `problem`.
    pub set: Vec<String>,
    /// Command-line counts (`--starts`, `--jobs`) and their values, for `problem`.
    pub counts: Vec<(&'static str, usize)>,
    /// The base the URDF alone is loaded with.
    pub base: BaseType,
    /// A trajectory CSV, the reader it goes through and the CSV target (problem) it is for.
    pub csv: Option<(CsvReader, usize, String)>,
    /// A name, for `names`.
    pub name: Option<String>,
}

impl Input {
    /// The input's files, as (file name, text), for saving it.
    pub fn files(&self) -> Vec<(String, String)> {
        let mut out = Vec::new();
        if let Some(p) = &self.problem {
            out.push(("problem.toml".to_owned(), p.clone()));
        }
        if !self.urdf.is_empty() {
            out.push(("robot.urdf".to_owned(), self.urdf.clone()));
        }
        if !self.set.is_empty() {
            out.push(("set.txt".to_owned(), self.set.join("\n")));
        }
        if !self.counts.is_empty() {
            let lines: Vec<String> = self
                .counts
                .iter()
                .map(|(o, v)| format!("{o} {v}"))
                .collect();
            out.push(("counts.txt".to_owned(), lines.join("\n")));
        }
        if let Some((reader, _, text)) = &self.csv {
            out.push((format!("{reader:?}.csv"), text.clone()));
        }
        if let Some(name) = &self.name {
            out.push(("name.txt".to_owned(), name.clone()));
        }
        out
    }
}

/// Per-kind figures of a run.
#[derive(Debug, Clone)]
pub struct KindReport {
    /// The kind.
    pub kind: Kind,
    /// Inputs tried.
    pub inputs: u64,
    /// Inputs that loaded without error.
    pub accepted: u64,
    /// Inputs that panicked.
    pub panics: u64,
    /// Inputs that took longer than [`HANG`].
    pub hangs: u64,
    /// The slowest input's time, number and seed.
    pub slowest: (Duration, u64, String),
    /// The time of all its inputs.
    pub total: Duration,
}

/// What a run found.
#[derive(Debug, Clone, Default)]
pub struct FuzzReport {
    /// Inputs tried.
    pub inputs: u64,
    /// Inputs that loaded without error.
    pub accepted: u64,
    /// Inputs whose load panicked (each a bug).
    pub panics: u64,
    /// Inputs that took longer than [`HANG`] (each a bug).
    pub hangs: u64,
    /// The first panicking and hanging inputs (up to 10 of each), with `panic` or `hang`.
    pub saved: Vec<(&'static str, Input)>,
    /// The slowest input's time and seed name.
    pub slowest: (Duration, String),
    /// Per kind, in the order of [`Kind::ALL`].
    pub kinds: Vec<KindReport>,
    /// The number of the next input to run (where a run that died repeats from).
    pub next: u64,
    /// Wall time of the run.
    pub wall: Duration,
}

/// A problem of the project loaded once, with a valid trajectory CSV for it and (built when
/// first needed) its NLP, for `csv` inputs.
struct CsvTarget {
    name: String,
    loaded: crate::problem::LoadedProblem,
    csv: String,
    nlp: std::cell::OnceCell<
        Option<crate::transcription::Transcription<crate::transcription::ModelMechanics>>,
    >,
}

/// Largest problem (coordinates × knots) whose NLP `check --at` inputs are built for (the
/// structure discovery takes seconds for the larger robots).
const AT_NLP_SIZE: usize = 7 * 40;

impl CsvTarget {
    fn new(seed: &Seed) -> Option<CsvTarget> {
        let problem = seed.problem.as_deref()?;
        let loaded =
            crate::problem::load_from_str(Path::new(&seed.name), problem, &seed.urdf, &[]).ok()?;
        let csv = trajectory_text(&loaded);
        Some(CsvTarget {
            name: seed.name.clone(),
            loaded,
            csv,
            nlp: std::cell::OnceCell::new(),
        })
    }

    /// The NLP for `check --at`, for a small problem only.
    fn nlp(
        &self,
    ) -> Option<&crate::transcription::Transcription<crate::transcription::ModelMechanics>> {
        self.nlp
            .get_or_init(|| {
                let spec = &self.loaded.spec;
                (spec.q_initial.len() * spec.knots <= AT_NLP_SIZE)
                    .then(|| crate::pipeline::build_nlp(spec).ok())
                    .flatten()
            })
            .as_ref()
    }
}

/// A trajectory CSV for `p` as `vito solve` writes its columns: a row per knot at the
/// problem's step, the initial pose moved a little, zero inputs and impulses.
fn trajectory_text(p: &crate::problem::LoadedProblem) -> String {
    use crate::files::trajectory_csv::{input_column_name, knot_time, number};
    let spec = &p.spec;
    let h = spec.time_steps.guess_step(spec.knots);
    let mut header = vec!["time [s]".to_owned()];
    header.extend(p.robot.coordinates.iter().map(|c| format!("{c} [m]")));
    header.extend(p.robot.coordinates.iter().map(|c| format!("{c}_dot [m/s]")));
    header.extend(
        p.robot
            .inputs
            .iter()
            .map(|i| format!("{} [N]", input_column_name(i))),
    );
    for c in &spec.contacts {
        header.push(format!("{}_normal [N·s]", c.name));
        header.push(format!("{}_friction_+x [N·s]", c.name));
        header.push(format!("{}_distance [m]", c.name));
    }
    header.push("slack".to_owned());
    let mut out = header.join(",");
    out.push('\n');
    for k in 0..spec.knots {
        let mut row = vec![number(knot_time(k, h))];
        row.extend(spec.q_initial.iter().map(|q| number(q + 1e-3 * k as f64)));
        row.extend(spec.q_initial.iter().map(|_| "0".to_owned()));
        let last = k + 1 == spec.knots;
        let interval = |n: usize, row: &mut Vec<String>| {
            row.extend((0..n).map(|_| if last { String::new() } else { "0".to_owned() }));
        };
        interval(p.robot.inputs.len(), &mut row);
        for _ in &spec.contacts {
            interval(2, &mut row);
            row.push("0.1".to_owned());
        }
        interval(1, &mut row);
        out.push_str(&row.join(","));
        out.push('\n');
    }
    out
}

/// How large the generated inputs get.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sizes {
    /// Up to the largest (expressions 100,000 deep, 10,001 links, 200,000 attributes or
    /// elements, CSVs of 100,000 rows), each large size rarely.
    Full,
    /// Only the small sizes (still around every limit: 63–65, 99–101), for a quick run.
    Small,
}

/// Runs one input through its library calls; `true` when every call accepted it.
fn load_once(input: &Input, targets: &[CsvTarget]) -> bool {
    use crate::files::input::{MAX_TEXT_BYTES, MAX_URDF_BYTES};
    // The commands refuse a file over these sizes before reading it.
    let over = |text: &str, max: u64| text.len() as u64 > max;
    if input
        .problem
        .as_deref()
        .is_some_and(|p| over(p, MAX_TEXT_BYTES))
        || over(&input.urdf, MAX_URDF_BYTES)
        || input
            .csv
            .as_ref()
            .is_some_and(|(_, _, t)| over(t, MAX_TEXT_BYTES))
    {
        return false;
    }
    if let Some(name) = &input.name {
        return names_once(name);
    }
    match (input.kind, &input.problem, &input.csv) {
        (_, _, Some((reader, t, text))) => read_csv_once(*reader, &targets[*t], text),
        (_, Some(problem), _) => {
            check_counts(&input.counts);
            let Ok(set) = input
                .set
                .iter()
                .map(|s| crate::problem::Override::parse(s))
                .collect::<Result<Vec<_>, _>>()
            else {
                return false;
            };
            crate::problem::load_from_str(Path::new("fuzz.toml"), problem, &input.urdf, &set)
                .is_ok()
        }
        _ => Model::from_urdf_str(&input.urdf, input.base).is_ok(),
    }
}

/// A name through the writers that put names into files; panics when a property breaks
/// (counted as a panic); `true` when the CSV reads the name back.
fn names_once(name: &str) -> bool {
    use crate::files::trajectory_csv::{ColumnUnits, Trajectory, read_csv, write_trajectory};
    // The page's script JSON.
    let value = serde_json::json!({ "title": name, "tracks": [{ "name": name }] });
    let script = crate::view::script_json(&value);
    assert!(
        !script.contains(['<', '>', '&', '\u{2028}', '\u{2029}']),
        "script JSON left markup"
    );
    assert_eq!(
        serde_json::from_str::<serde_json::Value>(&script)
            .ok()
            .as_ref(),
        Some(&value),
        "script JSON changed the value"
    );
    // A strip's title, label and attribute.
    let escaped = crate::files::names::xml_escape(name);
    let svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\"><title>{escaped}</title><text data-name=\"{escaped}\">{escaped}</text></svg>"
    );
    let doc = roxmltree::Document::parse(&svg).expect("the strip's XML parses");
    let text = doc
        .descendants()
        .find(|n| n.has_tag_name("text"))
        .expect("the text element");
    // XML 1.0 keeps every character but the controls other than tab, newline and carriage
    // return, and U+FFFE, U+FFFF (those become U+FFFD).
    let kept: String = name
        .chars()
        .map(|c| match c {
            '\t' | '\n' | '\r' => c,
            c if c < ' ' || c == '\u{fffe}' || c == '\u{ffff}' => '\u{fffd}',
            c => c,
        })
        .collect();
    assert_eq!(
        text.text().unwrap_or(""),
        kept,
        "the strip's text changed the name"
    );
    assert!(doc.descendants().all(|n| !n.has_tag_name("script")));
    assert_eq!(
        text.attribute("data-name").map(|a| !a.is_empty()),
        Some(!name.is_empty())
    );
    // A trajectory CSV with a coordinate and a contact so named.
    let names = [name.to_owned()];
    let (times, q, v) = ([0.0, 0.1], [vec![0.0], vec![0.5]], [vec![0.0], vec![5.0]]);
    let impulses = [vec![1.0]];
    let trajectory = Trajectory {
        times: &times,
        coordinate_names: &names,
        q: &q,
        v: &v,
        input_names: &[],
        u: &[],
        contact_names: &names,
        friction_directions: 2,
        normal_impulse: &impulses,
        friction_impulse: &[vec![vec![0.0, 0.0]]],
        world_impulse: &[],
        signed_distance: &[vec![0.0], vec![0.0]],
        slack: &[vec![0.0]],
        contact_positions: &[vec![[0.0, 0.0, 0.0]], vec![[0.0, 0.0, 0.5]]],
    };
    let units = ColumnUnits {
        time: "s".into(),
        length: "m".into(),
        coordinates: vec!["m".into()],
        inputs: Vec::new(),
        impulse: "N·s".into(),
    };
    let csv = write_trajectory(&trajectory, &units);
    let table = read_csv(&csv);
    // A name a problem file can give (no hidden characters, not padded, short, no column
    // named twice: loading refuses those) reads back.
    let clash = crate::files::trajectory_csv::repeated_column(
        &crate::files::trajectory_csv::columns(&names, &[], &names, 2, 1, &units),
    )
    .is_some();
    let plain = !name.is_empty()
        && name.trim() == name
        && name.len() <= 150
        && !clash
        && !name.chars().any(crate::files::names::is_hidden_char);
    if plain {
        let table = table.expect("vito's own CSV reads back");
        assert_eq!(table.column(name), Some(vec![0.0, 0.5]), "the coordinate");
        assert_eq!(
            table.column(&format!("{name}_normal")).map(|c| c[0]),
            Some(1.0),
            "the contact's impulse"
        );
    }
    plain
}

/// A CSV through `reader` for `target`, as the command does; for `simulate`, the input
/// policy the recording makes is asked for inputs at times before, in and after it.
fn read_csv_once(reader: CsvReader, target: &CsvTarget, text: &str) -> bool {
    use crate::sim::{Feedback, InputSource};
    let p = &target.loaded;
    let robot = &p.robot;
    match reader {
        CsvReader::WarmStart => crate::problem::warm_start_from_text(text, robot).is_ok(),
        CsvReader::Inputs | CsvReader::Track => {
            let Ok(r) = crate::pipeline::simulation::recorded_inputs(text, robot) else {
                return false;
            };
            let end = r.times.last().copied().unwrap_or(0.0);
            let source = if reader == CsvReader::Inputs {
                InputSource::Replay(r)
            } else {
                let gains = crate::pipeline::gains::parse_gains(
                    &p.tracking_gains,
                    &["all=10,1".to_owned()],
                    robot,
                )
                .unwrap_or_default();
                InputSource::Track {
                    reference: r,
                    gains,
                    feedback: if end > 1.0 {
                        Feedback::Implicit
                    } else {
                        Feedback::Explicit
                    },
                }
            };
            let q = &p.spec.q_initial;
            let v = vec![0.0; q.len()];
            let m = robot.inputs.len();
            for t in [-1.0, 0.0, 0.5 * end, end, end + 1.0, 1e300] {
                let u = source.step_input(m, t, 0.01, q, &v);
                std::hint::black_box(u);
            }
            true
        }
        CsvReader::At => match target.nlp() {
            Some(nlp) => {
                let contacts: Vec<String> =
                    p.spec.contacts.iter().map(|c| c.name.clone()).collect();
                crate::pipeline::trajectory_point::point_from_trajectory(
                    nlp, robot, &contacts, text,
                )
                .is_ok_and(|x| x.iter().all(|v| v.is_finite()))
            }
            None => crate::problem::warm_start_from_text(text, robot).is_ok(),
        },
    }
}

/// Generates (up to `sizes`) and runs the inputs numbered `inputs` (0-based) from `seeds`:
/// input i is drawn from its own generator ([`SeededRng::for_item`] of `seed` and i), so any
/// range repeats exactly the inputs a longer run gave it, and runs of disjoint ranges add up
/// to one run. `progress` is called every 1,000 inputs. A watchdog thread prints (on standard error) any input still
/// running after [`HANG`].
pub fn run(
    seeds: &[Seed],
    inputs: std::ops::Range<u64>,
    seed: u64,
    sizes: Sizes,
    mut progress: impl FnMut(&FuzzReport),
) -> FuzzReport {
    use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
    let mut report = FuzzReport {
        kinds: Kind::ALL
            .iter()
            .map(|&kind| KindReport {
                kind,
                inputs: 0,
                accepted: 0,
                panics: 0,
                hangs: 0,
                slowest: (Duration::ZERO, 0, String::new()),
                total: Duration::ZERO,
            })
            .collect(),
        next: inputs.start,
        ..FuzzReport::default()
    };
    let start = Instant::now();
    let targets: Vec<CsvTarget> = seeds.iter().filter_map(CsvTarget::new).collect();
    // The input running (u64::MAX: none) and when it started (ms since `start`).
    let running = AtomicU64::new(u64::MAX);
    let since = AtomicU64::new(0);
    let done = AtomicBool::new(false);
    std::thread::scope(|scope| {
        scope.spawn(|| {
            let mut warned = u64::MAX;
            while !done.load(Ordering::Relaxed) {
                std::thread::sleep(Duration::from_millis(200));
                let i = running.load(Ordering::Relaxed);
                let ms = start.elapsed().as_millis() as u64;
                if i != u64::MAX
                    && i != warned
                    && ms.saturating_sub(since.load(Ordering::Relaxed)) > HANG.as_millis() as u64
                {
                    eprintln!(
                        "fuzz: input {i} has run for more than {} s (repeat it with FIRST={i})",
                        HANG.as_secs()
                    );
                    warned = i;
                }
            }
        });
        for index in inputs.clone() {
            let mut rng = SeededRng::for_item(seed, index);
            let input = generate(seeds, &targets, sizes, index, &mut rng);
            if input.kind == Kind::Csv
                && let Some((CsvReader::At, t, _)) = &input.csv
            {
                // Built once, before the input's clock starts.
                let _ = targets[*t].nlp();
            }
            since.store(start.elapsed().as_millis() as u64, Ordering::Relaxed);
            running.store(index, Ordering::Relaxed);
            let t0 = process_cpu_time();
            let outcome = catch_unwind(AssertUnwindSafe(|| load_once(&input, &targets)));
            let elapsed = process_cpu_time().saturating_sub(t0);
            running.store(u64::MAX, Ordering::Relaxed);
            report.inputs += 1;
            report.next = index + 1;
            let k = &mut report.kinds[Kind::ALL.iter().position(|&k| k == input.kind).unwrap_or(0)];
            k.inputs += 1;
            k.total += elapsed;
            if elapsed > k.slowest.0 {
                k.slowest = (elapsed, index, input.seed.clone());
            }
            if elapsed > report.slowest.0 {
                report.slowest = (
                    elapsed,
                    format!("input {index}, {}, {}", input.kind.name(), input.seed),
                );
            }
            let hang = elapsed > HANG;
            if hang {
                k.hangs += 1;
                report.hangs += 1;
            }
            match outcome {
                Ok(true) => {
                    k.accepted += 1;
                    report.accepted += 1;
                }
                Ok(false) => {}
                Err(_) => {
                    k.panics += 1;
                    report.panics += 1;
                }
            }
            for (found, what) in [(outcome.is_err(), "panic"), (hang, "hang")] {
                if found && report.saved.iter().filter(|(w, _)| *w == what).count() < 10 {
                    report.saved.push((what, input.clone()));
                }
            }
            if report.inputs.is_multiple_of(1000) {
                report.wall = start.elapsed();
                progress(&report);
            }
        }
        done.store(true, Ordering::Relaxed);
    });
    report.wall = start.elapsed();
    report
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The generated `--starts` and `--jobs` fall on both sides of each limit, and the
    /// commands' check refuses exactly those past it.
    #[test]
    fn generated_counts_cross_their_limits() {
        let mut rng = SeededRng::new(7);
        let mut seen = std::collections::BTreeSet::new();
        for _ in 0..400 {
            let counts = generate::generated_counts(&mut rng);
            check_counts(&counts);
            for (option, value) in counts {
                let max = COUNTS.iter().find(|(o, _)| *o == option).map_or(0, |c| c.1);
                seen.insert((option, value == 0, value > max));
            }
        }
        for (option, _) in COUNTS {
            for side in [(true, false), (false, false), (false, true)] {
                assert!(
                    seen.contains(&(option, side.0, side.1)),
                    "{option} {side:?}"
                );
            }
        }
    }

    /// The mutator repeats for a seed and changes its input.
    #[test]
    fn mutations_repeat_and_change() {
        let text = "a = 1\nb = [2.5, -3]\n[c]\nd = \"x\"\n";
        let (mut r1, mut r2) = (SeededRng::new(5), SeededRng::new(5));
        let m1: Vec<String> = (0..50).map(|_| mutate(text, &mut r1)).collect();
        let m2: Vec<String> = (0..50).map(|_| mutate(text, &mut r2)).collect();
        assert_eq!(m1, m2);
        assert!(m1.iter().filter(|m| m.as_str() != text).count() > 40);
        assert_eq!(mutate::number_spans(text), vec![(4, 5), (11, 14), (16, 18)]);
    }
}
