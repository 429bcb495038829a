//! Mutations of a file's text: bytes, tokens, numbers, lines, hostile snippets.

use crate::random::SeededRng;

/// Numbers a mutation puts in place of a number.
pub(super) const NUMBERS: &[&str] = &[
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
pub(super) fn number_spans(text: &str) -> Vec<(usize, usize)> {
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
