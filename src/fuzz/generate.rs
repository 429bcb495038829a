//! The generated inputs: deep expressions, long chains, many attributes, mutated CSVs, and
//! the draw of one input of any kind.

use super::mutate::{NUMBERS, number_spans};
use super::{CsvReader, CsvTarget, Input, Kind, Seed, Sizes, mutate};
use crate::model::BaseType;
use crate::random::SeededRng;

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
/// Pieces a hostile name is made of: markup and its escapes, comment and CDATA openers,
/// quotes, commas, brackets, separators, controls, noncharacters, a byte-order mark.
const NAME_PIECES: &[&str] = &[
    "<!--",
    "-->",
    "<script>",
    "</script>",
    "</text>",
    "<![CDATA[",
    "]]>",
    "&amp;",
    "&",
    "&#0;",
    "<",
    ">",
    "\"",
    "'",
    ",",
    "\"\"",
    " [",
    "]",
    " [m]",
    "\u{2028}",
    "\u{2029}",
    "\\",
    "/",
    "\u{0}",
    "\u{1b}",
    "\t",
    "\n",
    "\r",
    "\u{feff}",
    "\u{fffe}",
    "\u{ffff}",
    "\u{202e}",
    "é",
    "😀",
    " ",
    "a",
    "foot",
    "left,foot",
    "time",
];

/// A generated name: pieces and random code points, up to 40 pieces (with `Full` sizes,
/// rarely, one piece repeated to 70,000 characters).
fn hostile_name(sizes: Sizes, rng: &mut SeededRng) -> String {
    let mut name = String::new();
    if sizes == Sizes::Full && rng.index(200) == 0 {
        let piece = NAME_PIECES[rng.index(NAME_PIECES.len())];
        return piece.repeat(70_000 / piece.chars().count().max(1));
    }
    for _ in 0..1 + rng.index(40) {
        if rng.index(4) == 0 {
            let code = match rng.index(3) {
                0 => rng.index(0x80) as u32,
                1 => rng.index(0x1_0000) as u32,
                _ => rng.index(0x11_0000) as u32,
            };
            name.extend(char::from_u32(code));
        } else {
            name.push_str(NAME_PIECES[rng.index(NAME_PIECES.len())]);
        }
    }
    name
}

pub(super) fn generate(
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
        counts: Vec::new(),
        base,
        csv: None,
        name: None,
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
        58..=61 => {
            input.kind = Kind::Attributes;
            input.urdf = attributes_urdf(&s.urdf, sizes, rng);
        }
        62..=67 => {
            input.kind = Kind::Names;
            let name = hostile_name(sizes, rng);
            input.seed = format!("generated name of {} characters", name.chars().count());
            input.name = Some(name);
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
    if input.kind == Kind::Problem {
        // Drawn after the input's own draws, so the file and URDF are what they were.
        input.counts = generated_counts(rng);
    }
    input
}

/// `--starts` and `--jobs` as a command line gives them: at, around and far past their
/// limits ([`super::COUNTS`]), 0, and any 64-bit number.
pub(super) fn generated_counts(rng: &mut SeededRng) -> Vec<(&'static str, usize)> {
    super::COUNTS
        .iter()
        .map(|&(option, max)| {
            let value = match rng.index(4) {
                0 => [
                    0,
                    1,
                    2,
                    max - 1,
                    max,
                    max + 1,
                    2 * max,
                    1_000_000_000,
                    usize::MAX,
                ][rng.index(9)],
                1 => rng.index(max + 2),
                2 => max.saturating_add(1 + rng.index(1 << 20)),
                _ => rng.next_u64() as usize,
            };
            (option, value)
        })
        .collect()
}
