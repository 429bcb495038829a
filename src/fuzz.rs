//! The fuzz harness: generated and mutated inputs fed in memory to the library calls the
//! commands make on what a user gives, each input of a named [`Kind`]:
//!
//! - `problem`, `urdf`: the project's own problem files and URDFs mutated by a seeded mutator
//!   (byte changes, token swaps, numbers replaced by NaN, ±inf, 1e308, −0 or huge integers,
//!   lines deleted or repeated, deep nesting, hostile snippets), through problem loading
//!   ([`crate::problem::load_from_str`], parsing and every validation check, the URDF
//!   included) and URDF loading ([`crate::model::Model::from_urdf_str`]);
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
//!   `vito check --at`.
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

/// Numbers a mutation puts in place of a number.
const NUMBERS: &[&str] = &[
    "nan",
    "NaN",
    "inf",
    "-inf",
    "+inf",
    "1e308",
    "-1e308",
    "1e999",
    "-0",
    "-0.0",
    "0",
    "1",
    "-1",
    "5e-324",
    "1e-320",
    "2147483648",
    "-2147483649",
    "4294967296",
    "9223372036854775807",
    "-9223372036854775808",
    "99999999999999999999",
    "1e12",
    "0x7f",
    "1_000",
    "3.",
    ".5",
    "1e",
    "",
];

/// Snippets a mutation inserts at a line start.
const SNIPPETS: &[&str] = &[
    "[solver.ipopt]\noutput_file = \"/tmp/vito-fuzz-victim\"\n",
    "option_file_name = \"/etc/passwd\"\n",
    "linear_solver = \"ma97\"\n",
    "knots = 1000000000\n",
    "knots = []\n",
    "name = \"\\u001b[31mred\"\n",
    "name = \"\"\n",
    "[output]\ndir = \"\"\nname = \"../../x\"\n",
    "warm_start = \"/dev/zero\"\n",
    "[[bounds]]\ncoordinate = \"x\"\nknots = []\nlower = inf\n",
    "[[terrain.step]]\nedge_x = 0\nrise = 1e308\nwidth = 5e-324\n",
    "[[periodic]]\ncoordinate = \"x\"\n",
    "[[cost]]\ntype = \"time\"\nweight = nan\n",
    "<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"a\"/></joint>\n",
    "<loop_joint name=\"l\" type=\"continuous\"><parent link=\"a\"/><child link=\"a\"/></loop_joint>\n",
    "<transmission name=\"t\"><joint name=\"x\"/></transmission>\n",
    "<limit lower=\"nan\" upper=\"-inf\" effort=\"-1\" velocity=\"nan\"/>\n",
    "<origin xyz=\"nan 1e308 -0\" rpy=\"inf 0 0\"/>\n",
    "<!DOCTYPE r [<!ENTITY a \"aaaaaaaaaa\">]>\n",
];

/// One mutation of `text`, chosen and placed by `rng`.
fn mutate_once(text: &mut String, rng: &mut SeededRng) {
    let len = text.len();
    let at = |rng: &mut SeededRng| {
        let mut i = if len == 0 { 0 } else { rng.index(len + 1) };
        while !text.is_char_boundary(i) {
            i -= 1;
        }
        i
    };
    match rng.index(9) {
        // A character replaced by a random ASCII one (control characters included).
        0 if len > 0 => {
            let i = at(rng).min(len - 1);
            let mut j = i + 1;
            while !text.is_char_boundary(j) {
                j += 1;
            }
            let c = char::from(rng.index(128) as u8);
            text.replace_range(i..j, c.encode_utf8(&mut [0; 4]));
        }
        // A number replaced.
        1 | 2 => {
            let numbers: Vec<(usize, usize)> = number_spans(text);
            if let Some(&(a, b)) = numbers.get(rng.index(numbers.len().max(1))) {
                text.replace_range(a..b, NUMBERS[rng.index(NUMBERS.len())]);
            }
        }
        // Two tokens swapped.
        3 => {
            let tokens = token_spans(text);
            if tokens.len() >= 2 {
                let (mut a, mut b) = (
                    tokens[rng.index(tokens.len())],
                    tokens[rng.index(tokens.len())],
                );
                if a.0 > b.0 {
                    std::mem::swap(&mut a, &mut b);
                }
                if a.1 <= b.0 {
                    let (ta, tb) = (text[a.0..a.1].to_owned(), text[b.0..b.1].to_owned());
                    text.replace_range(b.0..b.1, &ta);
                    text.replace_range(a.0..a.1, &tb);
                }
            }
        }
        // A line deleted or repeated.
        4 | 5 => {
            let lines: Vec<&str> = text.split_inclusive('\n').collect();
            if !lines.is_empty() {
                let k = rng.index(lines.len());
                let mut out = String::with_capacity(text.len() + 200);
                for (i, line) in lines.iter().enumerate() {
                    if i != k || rng.index(2) == 0 {
                        out.push_str(line);
                    }
                    if i == k {
                        for _ in 0..rng.index(3) {
                            out.push_str(line);
                        }
                    }
                }
                *text = out;
            }
        }
        // Deep nesting, TOML or XML.
        6 => {
            let depth = [10, 100, 1000, 100_000][rng.index(4)];
            let i = at(rng);
            let nest = match rng.index(3) {
                0 => format!("x = {}{}\n", "[".repeat(depth), "]".repeat(depth)),
                1 => format!("x = {}1{}\n", "{a=".repeat(depth), "}".repeat(depth)),
                _ => format!("{}{}", "<a>".repeat(depth), "</a>".repeat(depth)),
            };
            text.insert_str(i, &nest);
        }
        // A hostile snippet at a line start.
        7 => {
            let starts: Vec<usize> = std::iter::once(0)
                .chain(text.match_indices('\n').map(|(i, _)| i + 1))
                .collect();
            let i = starts[rng.index(starts.len())];
            text.insert_str(i, SNIPPETS[rng.index(SNIPPETS.len())]);
        }
        // A chunk copied elsewhere.
        _ => {
            let (a, b) = (at(rng), at(rng));
            let (a, b) = (a.min(b), a.max(b).min(a.min(b) + 400));
            let mut b = b;
            while !text.is_char_boundary(b) {
                b -= 1;
            }
            let chunk = text[a..b].to_owned();
            let i = at(rng);
            text.insert_str(i, &chunk);
        }
    }
}

/// Byte ranges of the numbers in `text` (a digit, sign or dot run containing a digit).
fn number_spans(text: &str) -> Vec<(usize, usize)> {
    let bytes = text.as_bytes();
    let mut spans = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i].is_ascii_digit() {
            let mut a = i;
            while a > 0 && matches!(bytes[a - 1], b'-' | b'+' | b'.') {
                a -= 1;
            }
            let mut b = i;
            while b < bytes.len()
                && (bytes[b].is_ascii_alphanumeric()
                    || matches!(bytes[b], b'.' | b'-' | b'+' | b'_'))
            {
                b += 1;
            }
            spans.push((a, b));
            i = b;
        } else {
            i += 1;
        }
    }
    spans
}

/// Byte ranges of the words and punctuation marks of `text`.
fn token_spans(text: &str) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut start = None;
    for (i, c) in text.char_indices() {
        let word = c.is_alphanumeric() || c == '_' || c == '.';
        match (start, word) {
            (None, true) => start = Some(i),
            (Some(s), false) => {
                spans.push((s, i));
                start = None;
            }
            _ => {}
        }
        if !word && !c.is_whitespace() {
            spans.push((i, i + c.len_utf8()));
        }
    }
    if let Some(s) = start {
        spans.push((s, text.len()));
    }
    spans
}

/// `text` after one to four mutations.
pub fn mutate(text: &str, rng: &mut SeededRng) -> String {
    let mut out = text.to_owned();
    for _ in 0..=rng.index(4) {
        mutate_once(&mut out, rng);
    }
    out
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
}

impl Kind {
    /// Every kind, in the order reports list them.
    pub const ALL: [Kind; 6] = [
        Kind::Problem,
        Kind::Urdf,
        Kind::Expression,
        Kind::Chain,
        Kind::Attributes,
        Kind::Csv,
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
    /// The base the URDF alone is loaded with.
    pub base: BaseType,
    /// A trajectory CSV, the reader it goes through and the CSV target (problem) it is for.
    pub csv: Option<(CsvReader, usize, String)>,
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
        if let Some((reader, _, text)) = &self.csv {
            out.push((format!("{reader:?}.csv"), text.clone()));
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

/// Sizes from `small`, and from `large` one time in `rare` when `sizes` allows.
fn size(rng: &mut SeededRng, sizes: Sizes, small: &[usize], large: &[usize], rare: usize) -> usize {
    let (a, b) = (rng.index(rare), rng.index(small.len().max(large.len())));
    if a == 0 && sizes == Sizes::Full {
        large[b % large.len()]
    } else {
        small[b % small.len()]
    }
}

/// Nesting depths of the `expression` inputs.
const DEPTHS: &[usize] = &[1, 8, 32, 63, 64, 65, 100, 1000];
const DEEP: &[usize] = &[20_000, 30_000, 50_000, 100_000];

/// An expression nested `d` deep, one of several shapes.
fn deep_expression(d: usize, rng: &mut SeededRng) -> String {
    match rng.index(8) {
        0 => format!("{}1{}", "(".repeat(d), ")".repeat(d)),
        1 => format!("{}1", "-".repeat(d)),
        2 => format!("{}1{}", "-(".repeat(d), ")".repeat(d)),
        3 => format!("{}1", "(".repeat(d)),
        4 => format!("{}1", "1+".repeat(d)),
        5 => format!("{}1{}", "sin(".repeat(d), ")".repeat(d)),
        6 => format!("{}1", "+-".repeat(d)),
        _ => format!("{}mu{}", "(2*".repeat(d), ")".repeat(d)),
    }
}

/// The `section.key` paths of the lines `key = <number>` of a TOML text (outside arrays of
/// tables).
fn numeric_paths(text: &str) -> Vec<String> {
    let mut section: Option<String> = Some(String::new());
    let mut out = Vec::new();
    for line in text.lines() {
        let line = line.trim();
        if line.starts_with("[[") {
            section = None;
        } else if let Some(name) = line.strip_prefix('[').and_then(|l| l.strip_suffix(']')) {
            section = Some(name.trim().to_owned());
        } else if let (Some(sec), Some((key, value))) = (&section, line.split_once('=')) {
            let value = value.split('#').next().unwrap_or("").trim();
            if value.parse::<f64>().is_ok() {
                let key = key.trim();
                out.push(if sec.is_empty() {
                    key.to_owned()
                } else {
                    format!("{sec}.{key}")
                });
            }
        }
    }
    out
}

/// A problem with a deep expression, key path or TOML nesting: (text, `--set` arguments).
fn expression_input(problem: &str, sizes: Sizes, rng: &mut SeededRng) -> (String, Vec<String>) {
    let d = size(rng, sizes, DEPTHS, DEEP, 16);
    let mut text = problem.to_owned();
    let mut set = Vec::new();
    match rng.index(6) {
        // A number of the file replaced by a deep expression.
        0 | 1 => {
            let spans = number_spans(&text);
            if let Some(&(a, b)) = spans.get(rng.index(spans.len().max(1))) {
                let e = deep_expression(d, rng);
                text.replace_range(a..b, &format!("\"= {e}\""));
            }
        }
        // A numeric field set to a deep expression with --set.
        2 => {
            let paths = numeric_paths(&text);
            let path = paths
                .get(rng.index(paths.len().max(1)))
                .cloned()
                .unwrap_or_else(|| "slack.weight".to_owned());
            set.push(format!("{path}=\"= {}\"", deep_expression(d, rng)));
        }
        // A long --set key path, or a deeply nested --set value.
        3 => set.push(match rng.index(4) {
            0 => format!("{}b=1", "a.".repeat(d)),
            1 => format!("a{}=1", "[0]".repeat(d)),
            2 => format!("a={}{}", "[".repeat(d), "]".repeat(d)),
            _ => format!("horizon.{}=1", "x.".repeat(d)),
        }),
        // Deep TOML: a table header or dotted key of `d` parts, nested arrays or tables.
        _ => {
            let nest = match rng.index(4) {
                0 => format!("[{}b]\nx = 1\n", "a.".repeat(d)),
                1 => format!("{}b = 1\n", "a.".repeat(d)),
                2 => format!("x = {}1{}\n", "[".repeat(d), "]".repeat(d)),
                _ => format!("x = {}1{}\n", "{a=".repeat(d), "}".repeat(d)),
            };
            let starts: Vec<usize> = std::iter::once(0)
                .chain(text.match_indices('\n').map(|(i, _)| i + 1))
                .collect();
            text.insert_str(starts[rng.index(starts.len())], &nest);
        }
    }
    (text, set)
}

const INERTIAL: &str = "<inertial><mass value=\"0.1\"/><inertia ixx=\"0.01\" ixy=\"0\" \
     ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial>";

/// A generated URDF of `n` links (plus a root): a chain, tree, star, mimic chain, chain with
/// contacts and transmissions, or loops.
fn chain_urdf(n: usize, rng: &mut SeededRng) -> String {
    let shape = rng.index(7);
    let mut out = format!(
        "<?xml version=\"1.0\"?>\n<robot name=\"gen\">\n<link name=\"l0\">{INERTIAL}</link>\n"
    );
    for i in 1..=n {
        let contact = if shape == 4 && i % 3 == 0 {
            "<collision><geometry><sphere radius=\"0\"/></geometry></collision>"
        } else {
            ""
        };
        out.push_str(&format!("<link name=\"l{i}\">{INERTIAL}{contact}</link>\n"));
        let (parent, kind) = match shape {
            // A serial chain of revolute joints.
            0 | 4 | 6 => (i - 1, "revolute"),
            // A binary tree, moving near the root, fixed below.
            1 => ((i - 1) / 2, if i < 16 { "revolute" } else { "fixed" }),
            // A fixed-joint star.
            2 => (0, "fixed"),
            // A fixed-joint chain.
            3 => (i - 1, "fixed"),
            // A chain each of whose joints mimics the one before.
            _ => (i - 1, "revolute"),
        };
        let mimic = if shape == 5 && i > 1 {
            format!(
                "<mimic joint=\"j{}\" multiplier=\"1\" offset=\"0\"/>",
                i - 1
            )
        } else {
            String::new()
        };
        out.push_str(&format!(
            "<joint name=\"j{i}\" type=\"{kind}\"><parent link=\"l{parent}\"/>\
             <child link=\"l{i}\"/><origin xyz=\"0 0 0.1\" rpy=\"0 0 0\"/><axis xyz=\"0 1 0\"/>\
             <limit lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"10\"/>{mimic}</joint>\n"
        ));
        if shape == 4 {
            out.push_str(&format!(
                "<transmission name=\"t{i}\"><actuator name=\"a{i}\"/><joint name=\"j{i}\"/></transmission>\n"
            ));
        }
        if shape == 6 && i >= 2 {
            out.push_str(&format!(
                "<loop_joint name=\"c{i}\" type=\"continuous\"><axis xyz=\"0 1 0\"/>\
                 <link1 link=\"l{}\" xyz=\"0 0 0\" rpy=\"0 0 0\"/><link2 link=\"l{i}\" xyz=\"0 0 0\" \
                 rpy=\"0 0 0\"/></loop_joint>\n",
                i - 2
            ));
        }
    }
    out.push_str("</robot>\n");
    out
}

/// Counts of the `attributes` inputs.
const COUNTS: &[usize] = &[2, 10, 63, 64, 65, 500, 1000];
const MANY: &[usize] = &[10_000, 40_000, 200_000];

/// A URDF of the project with many attributes on one element or many elements added.
fn attributes_urdf(urdf: &str, sizes: Sizes, rng: &mut SeededRng) -> String {
    let k = size(rng, sizes, COUNTS, MANY, 40);
    let repeat = |f: &dyn Fn(usize) -> String| (0..k).map(f).collect::<String>();
    let added = match rng.index(9) {
        0 => {
            format!(
                "<link name=\"many\" {}>{INERTIAL}</link>\n<joint name=\"jm\" type=\"fixed\">\
                 <parent link=\"{}\"/><child link=\"many\"/></joint>\n",
                repeat(&|i| format!("a{i}=\"{i}\" ")),
                first_link(urdf)
            )
        }
        1 => {
            format!(
                "<link name=\"many\">{INERTIAL}{}</link>\n<joint name=\"jm\" type=\"fixed\">\
                 <parent link=\"{}\"/><child link=\"many\"/></joint>\n",
                repeat(&|i| format!(
                    "<visual><geometry><box size=\"0.1 0.1 0.1\"/></geometry>\
                     <material name=\"m{i}\"/></visual>"
                )),
                first_link(urdf)
            )
        }
        2 => repeat(&|i| format!("<material name=\"m{i}\"><color rgba=\"1 0 0 1\"/></material>\n")),
        3 => repeat(&|i| format!("<gazebo reference=\"x{i}\"/>\n")),
        4 => repeat(&|i| {
            format!("<transmission name=\"t{i}\"><joint name=\"j{i}\"/></transmission>\n")
        }),
        5 => repeat(&|i| {
            format!(
                "<loop_joint name=\"c{i}\" type=\"continuous\"><link1 link=\"x{i}\" xyz=\"0 0 0\" \
                     rpy=\"0 0 0\"/><link2 link=\"y{i}\" xyz=\"0 0 0\" rpy=\"0 0 0\"/></loop_joint>\n"
            )
        }),
        6 => repeat(&|i| format!("<link name=\"x{i}\"/>\n")),
        7 => repeat(&|i| format!("<!-- {i} --><?pi {i}?>\n")),
        _ => {
            format!("<link name=\"long\" extra=\"{}\"/>\n", "x".repeat(k * 50))
        }
    };
    match urdf.rfind("</robot>") {
        Some(i) => {
            let mut out = urdf.to_owned();
            out.insert_str(i, &added);
            out
        }
        None => format!("{urdf}{added}"),
    }
}

/// The name of the first `<link>` of a URDF (`base` if none is found).
fn first_link(urdf: &str) -> &str {
    urdf.split("<link name=\"")
        .nth(1)
        .and_then(|s| s.split('"').next())
        .unwrap_or("base")
}

/// A trajectory CSV after one to three CSV-shaped mutations (or the text mutator).
fn mutate_csv(csv: &str, sizes: Sizes, rng: &mut SeededRng) -> String {
    if rng.index(4) == 0 {
        return mutate(csv, rng);
    }
    let mut rows: Vec<Vec<String>> = csv
        .lines()
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect();
    let mut prefix = String::new();
    let mut crlf = false;
    for _ in 0..=rng.index(3) {
        let (nr, nc) = (rows.len(), rows.first().map_or(0, Vec::len));
        if nr < 2 || nc == 0 {
            break;
        }
        let (r, c) = (1 + rng.index(nr - 1), rng.index(nc));
        match rng.index(13) {
            // A cell made NaN, ±inf, huge, empty or not a number.
            0 | 1 => {
                if let Some(cell) = rows[r].get_mut(c) {
                    *cell = NUMBERS[rng.index(NUMBERS.len())].to_owned();
                }
            }
            // A header renamed: another column's name, a word, nothing, quotes, a control
            // character, a long name.
            2 => {
                let other = rows[0][rng.index(nc)].clone();
                rows[0][c] = match rng.index(6) {
                    0 => other,
                    1 => "x".to_owned(),
                    2 => String::new(),
                    3 => "\"q\" [m]".to_owned(),
                    4 => "a\u{1b}[31m\u{202e}".to_owned(),
                    _ => "n".repeat(300),
                };
            }
            // A column repeated.
            3 => {
                for row in rows.iter_mut() {
                    if let Some(cell) = row.get(c).cloned() {
                        row.push(cell);
                    }
                }
            }
            // A ragged row.
            4 => {
                if rng.index(2) == 0 {
                    rows[r].pop();
                } else {
                    rows[r].push("0".to_owned());
                }
            }
            // A row repeated many times.
            5 => {
                let k = size(rng, sizes, &[2, 10, 100], &[10_000, 100_000], 50);
                let row = rows[r].clone();
                for _ in 0..k {
                    rows.insert(r, row.clone());
                }
            }
            // Times scaled.
            6 => {
                let f = [1e300, -1.0, 0.0, 1e-300, 1e9][rng.index(5)];
                for row in rows.iter_mut().skip(1) {
                    if let Some(t) = row
                        .first_mut()
                        .and_then(|t| Some((t.parse::<f64>().ok()?, t)))
                    {
                        *t.1 = crate::files::trajectory_csv::number(t.0 * f);
                    }
                }
            }
            // Two rows swapped.
            7 => {
                let s = 1 + rng.index(nr - 1);
                rows.swap(r, s);
            }
            // A column removed.
            8 => {
                for row in rows.iter_mut() {
                    if c < row.len() {
                        row.remove(c);
                    }
                }
            }
            // Rows removed: all but the header, or down to one.
            9 => rows.truncate(1 + rng.index(2)),
            // Other encodings: CRLF, a byte-order mark, quoted cells, padded cells.
            10 => match rng.index(3) {
                0 => crlf = true,
                1 => prefix = "\u{feff}".to_owned(),
                _ => {
                    for cell in rows[r].iter_mut() {
                        *cell = format!(" \"{cell}\" ");
                    }
                }
            },
            // Many columns added.
            11 => {
                let k = size(rng, sizes, &[1, 10, 100], &[10_000], 50);
                for (i, row) in rows.iter_mut().enumerate() {
                    for j in 0..k {
                        row.push(if i == 0 {
                            format!("extra{j}")
                        } else {
                            "1".to_owned()
                        });
                    }
                }
            }
            // Another file's text in place of the CSV.
            _ => {
                return [
                    "root:x:0:0:root:/root:/bin/bash\ndaemon:x:1:1::/usr/sbin:/usr/sbin/nologin\n",
                    "-----BEGIN OPENSSH PRIVATE KEY-----\nb3BlbnNzaC1rZXktdjEAAAAABG5vbmUAAAAEbm9uZQ\n",
                    "name = \"x\"\n[robot]\nurdf = \"r.urdf\"\n",
                    "",
                    "time\n",
                    "time,time\n0,0\n",
                ][rng.index(6)]
                .to_owned();
            }
        }
    }
    let newline = if crlf { "\r\n" } else { "\n" };
    let mut out = prefix;
    for row in rows {
        out.push_str(&row.join(","));
        out.push_str(newline);
    }
    out
}

/// Draws input number `index` from `rng`.
fn generate(
    seeds: &[Seed],
    targets: &[CsvTarget],
    sizes: Sizes,
    index: u64,
    rng: &mut SeededRng,
) -> Input {
    let bases = [BaseType::Fixed, BaseType::Planar, BaseType::Floating];
    let s = &seeds[rng.index(seeds.len())];
    let roll = rng.index(100);
    let base = bases[rng.index(3)];
    let mut input = Input {
        kind: Kind::Problem,
        index,
        seed: s.name.clone(),
        problem: None,
        urdf: String::new(),
        set: Vec::new(),
        base,
        csv: None,
    };
    let problem_seeds: Vec<&Seed> = seeds.iter().filter(|s| s.problem.is_some()).collect();
    match roll {
        0..=39 => match &s.problem {
            Some(p) => {
                (input.problem, input.urdf) = match rng.index(4) {
                    0 => (Some(p.clone()), mutate(&s.urdf, rng)),
                    1 => (Some(mutate(p, rng)), mutate(&s.urdf, rng)),
                    _ => (Some(mutate(p, rng)), s.urdf.clone()),
                };
            }
            None => {
                input.kind = Kind::Urdf;
                input.urdf = mutate(&s.urdf, rng);
            }
        },
        40..=51 if !problem_seeds.is_empty() => {
            let s = problem_seeds[rng.index(problem_seeds.len())];
            input.kind = Kind::Expression;
            input.seed = s.name.clone();
            let (text, set) = expression_input(s.problem.as_deref().unwrap_or(""), sizes, rng);
            input.problem = Some(text);
            input.set = set;
            input.urdf = s.urdf.clone();
        }
        52..=57 => {
            input.kind = Kind::Chain;
            let n = size(
                rng,
                sizes,
                &[1, 2, 10, 50, 99, 100, 101, 150],
                &[1000, 5000, 10_000, 10_001],
                50,
            );
            input.seed = format!("generated, {n} links");
            input.urdf = chain_urdf(n, rng);
            if rng.index(4) == 0 {
                input.urdf = mutate(&input.urdf, rng);
            }
        }
        58..=63 => {
            input.kind = Kind::Attributes;
            input.urdf = attributes_urdf(&s.urdf, sizes, rng);
        }
        _ if !targets.is_empty() => {
            let t = rng.index(targets.len());
            input.kind = Kind::Csv;
            input.seed = targets[t].name.clone();
            let reader = [
                CsvReader::WarmStart,
                CsvReader::Inputs,
                CsvReader::Track,
                CsvReader::At,
            ][rng.index(4)];
            input.csv = Some((reader, t, mutate_csv(&targets[t].csv, sizes, rng)));
        }
        _ => {
            input.kind = Kind::Urdf;
            input.urdf = mutate(&s.urdf, rng);
        }
    }
    input
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
    match (input.kind, &input.problem, &input.csv) {
        (_, _, Some((reader, t, text))) => read_csv_once(*reader, &targets[*t], text),
        (_, Some(problem), _) => {
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

/// Generates (up to `sizes`) and runs the inputs numbered `inputs` (0-based; earlier ones are
/// generated but not run, to repeat part of a run) from `seeds` with generator seed `seed`; `progress` is
/// called every 1,000 inputs. A watchdog thread prints (on standard error) any input still
/// running after [`HANG`].
pub fn run(
    seeds: &[Seed],
    inputs: std::ops::Range<u64>,
    seed: u64,
    sizes: Sizes,
    mut progress: impl FnMut(&FuzzReport),
) -> FuzzReport {
    use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
    let mut rng = SeededRng::new(seed);
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
        for index in 0..inputs.end {
            let input = generate(seeds, &targets, sizes, index, &mut rng);
            if index < inputs.start {
                continue;
            }
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

    /// The mutator repeats for a seed and changes its input.
    #[test]
    fn mutations_repeat_and_change() {
        let text = "a = 1\nb = [2.5, -3]\n[c]\nd = \"x\"\n";
        let (mut r1, mut r2) = (SeededRng::new(5), SeededRng::new(5));
        let m1: Vec<String> = (0..50).map(|_| mutate(text, &mut r1)).collect();
        let m2: Vec<String> = (0..50).map(|_| mutate(text, &mut r2)).collect();
        assert_eq!(m1, m2);
        assert!(m1.iter().filter(|m| m.as_str() != text).count() > 40);
        assert_eq!(number_spans(text), vec![(4, 5), (11, 14), (16, 18)]);
    }
}
