//! The fuzz harness: the project's own valid problem files and URDFs, mutated by a seeded
//! mutator (byte changes, token swaps, numbers replaced by NaN, ±inf, 1e308, −0 or huge
//! integers, lines deleted or repeated, deep nesting, hostile snippets), fed to problem
//! loading ([`crate::problem::load_from_str`], parsing and every validation check, the
//! URDF included) and to URDF loading ([`crate::model::Model::from_urdf_str`]), all in
//! memory. An input must end in `Ok` or an error: a panic is caught and counted, an abort or
//! stack overflow ends the run. `examples/fuzz.rs` runs it (`make fuzz`); a short run is in
//! the test suite.

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

/// What a run found.
#[derive(Debug, Clone, Default)]
pub struct FuzzReport {
    /// Inputs tried.
    pub inputs: u64,
    /// Inputs that loaded without error.
    pub accepted: u64,
    /// Inputs whose load panicked (each a bug), with the first few inputs.
    pub panics: u64,
    /// The first panicking inputs: (seed name, mutated problem text, mutated URDF text).
    pub panic_inputs: Vec<(String, Option<String>, String)>,
    /// The slowest input's time and seed name.
    pub slowest: (Duration, String),
    /// Wall time of the run.
    pub wall: Duration,
}

/// Loads one input; `Ok(true)` when it was accepted.
fn load_once(problem: Option<&str>, urdf: &str, base: BaseType) -> bool {
    match problem {
        Some(text) => {
            crate::problem::load_from_str(Path::new("fuzz.toml"), text, urdf, &[]).is_ok()
        }
        None => Model::from_urdf_str(urdf, base).is_ok(),
    }
}

/// Mutates and loads the inputs numbered `inputs` (0-based; earlier ones are drawn but not
/// loaded, to repeat part of a run) from `seeds` with generator seed `seed`; `progress` is
/// called every 10,000 inputs.
pub fn run(
    seeds: &[Seed],
    inputs: std::ops::Range<u64>,
    seed: u64,
    mut progress: impl FnMut(&FuzzReport),
) -> FuzzReport {
    let mut rng = SeededRng::new(seed);
    let mut report = FuzzReport::default();
    let start = Instant::now();
    let bases = [BaseType::Fixed, BaseType::Planar, BaseType::Floating];
    for index in 0..inputs.end {
        let s = &seeds[rng.index(seeds.len())];
        let (problem, urdf) = match &s.problem {
            Some(p) => match rng.index(4) {
                0 => (Some(p.clone()), mutate(&s.urdf, &mut rng)),
                1 => (Some(mutate(p, &mut rng)), mutate(&s.urdf, &mut rng)),
                _ => (Some(mutate(p, &mut rng)), s.urdf.clone()),
            },
            None => (None, mutate(&s.urdf, &mut rng)),
        };
        let base = bases[rng.index(3)];
        if index < inputs.start {
            continue;
        }
        let t0 = Instant::now();
        let outcome = catch_unwind(AssertUnwindSafe(|| {
            load_once(problem.as_deref(), &urdf, base)
        }));
        let elapsed = t0.elapsed();
        report.inputs += 1;
        match outcome {
            Ok(true) => report.accepted += 1,
            Ok(false) => {}
            Err(_) => {
                report.panics += 1;
                if report.panic_inputs.len() < 10 {
                    report.panic_inputs.push((
                        format!("input {index} from {}", s.name),
                        problem,
                        urdf,
                    ));
                }
            }
        }
        if elapsed > report.slowest.0 {
            report.slowest = (elapsed, s.name.clone());
        }
        if report.inputs % 10_000 == 0 {
            report.wall = start.elapsed();
            progress(&report);
        }
    }
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
