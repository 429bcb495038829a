//! Problem families: a `[parameters]` table of named numbers with defaults, and derived
//! fields written as string expressions that start with `=`:
//!
//! ```toml
//! [parameters]
//! stride_hz = 10
//!
//! [horizon]
//! total_time = ["= 0.9 / stride_hz", "= 1.1 / stride_hz"]
//! ```
//!
//! An expression holds numbers, parameter names, `+ - * /`, unary minus and parentheses,
//! nothing else; it is evaluated once, before the file is checked, and replaced by its
//! number. `--set stride_hz=30` (or `--set parameters.stride_hz=30`) changes a parameter.

#![warn(missing_docs)]

use std::collections::BTreeMap;

use crate::problem::source::nearest;

/// The table of a problem file that declares its parameters.
pub const PARAMETERS: &str = "parameters";

/// Why a parameter or an expression cannot be used; `field` is the TOML path.
#[derive(Debug, Clone, PartialEq)]
pub struct FamilyError {
    /// TOML path of the parameter or of the field holding the expression.
    pub field: String,
    /// What is wrong and how to fix it.
    pub message: String,
}

/// Deepest nesting of parentheses and unary signs in an expression (and of `.`-separated
/// keys in a `--set` path): far beyond any real use, far below what overflows the stack.
pub const MAX_NESTING: usize = 64;

/// Longest expression echoed in an error message (characters); longer ones are cut.
const ECHO_CHARS: usize = 60;

/// `s` as an error message quotes it: at most [`ECHO_CHARS`] characters.
pub(crate) fn echo(s: &str) -> String {
    if s.chars().count() <= ECHO_CHARS {
        s.to_owned()
    } else {
        let head: String = s.chars().take(ECHO_CHARS).collect();
        format!("{head}… ({} characters)", s.chars().count())
    }
}

/// The declared parameters (name → value, defaults with `--set` applied).
pub type Parameters = BTreeMap<String, f64>;

/// Takes `[parameters]` out of `root` (so the schema never sees it) and checks it: each a
/// finite number named like an identifier that is not also a top-level key of the file.
pub fn take_parameters(root: &mut toml::Table) -> Result<Parameters, FamilyError> {
    let Some(value) = root.remove(PARAMETERS) else {
        return Ok(Parameters::new());
    };
    let table = value.as_table().ok_or_else(|| FamilyError {
        field: PARAMETERS.into(),
        message: "must be a table of numbers, e.g. `[parameters]` then `stride_hz = 10`".into(),
    })?;
    let mut parameters = Parameters::new();
    for (name, value) in table {
        let field = format!("{PARAMETERS}.{name}");
        if !is_identifier(name) {
            return Err(FamilyError {
                field,
                message: "a parameter name must be letters, digits and `_`, starting with a \
                          letter or `_`"
                    .into(),
            });
        }
        if root.contains_key(name) {
            return Err(FamilyError {
                field,
                message: format!(
                    "`{name}` is also a top-level key of the file, so `--set {name}=…` would be \
                     ambiguous: rename the parameter"
                ),
            });
        }
        let number = match value {
            toml::Value::Integer(i) => *i as f64,
            toml::Value::Float(x) => *x,
            other => {
                return Err(FamilyError {
                    field,
                    message: format!(
                        "a parameter's default must be a number, not {}",
                        other.type_str()
                    ),
                });
            }
        };
        if !number.is_finite() {
            return Err(FamilyError {
                field,
                message: format!("the default {number} is not a finite number"),
            });
        }
        parameters.insert(name.clone(), number);
    }
    Ok(parameters)
}

/// Replaces every string value starting with `=` in `root` by the number its expression
/// evaluates to (an integer when the result is a whole number that fits, else a float).
pub fn evaluate_expressions(
    root: &mut toml::Table,
    parameters: &Parameters,
) -> Result<(), FamilyError> {
    for (key, value) in root.iter_mut() {
        evaluate_value(value, key, parameters)?;
    }
    Ok(())
}

/// Whether any string in `value` is an expression.
pub fn has_expressions(root: &toml::Table) -> bool {
    fn any(key: &str, value: &toml::Value) -> bool {
        if is_text_field(key) {
            return false;
        }
        match value {
            toml::Value::String(s) => expression_of(s).is_some(),
            toml::Value::Array(a) => a.iter().any(|v| any(key, v)),
            toml::Value::Table(t) => t.iter().any(|(k, v)| any(k, v)),
            _ => false,
        }
    }
    root.iter().any(|(k, v)| any(k, v))
}

fn expression_of(s: &str) -> Option<&str> {
    s.trim_start().strip_prefix('=')
}

/// The schema's fields that hold only text (names, paths, choices), by their key: a string
/// there is never an expression, whatever it starts with (`name = "=x"` is the name `=x`).
const TEXT_FIELDS: [&str; 17] = [
    "name",
    "description",
    "urdf",
    "base",
    "units",
    "link",
    "coordinate",
    "mode",
    "restart",
    "warm_start",
    "report",
    "forward",
    "vertical",
    "integrator",
    "hessian",
    "dir",
    "type",
];

/// Whether the field at TOML path `field` holds only text ([`TEXT_FIELDS`]).
fn is_text_field(field: &str) -> bool {
    let key = field.rsplit('.').next().unwrap_or(field);
    let key = key.split('[').next().unwrap_or(key);
    TEXT_FIELDS.contains(&key)
}

fn evaluate_value(
    value: &mut toml::Value,
    field: &str,
    parameters: &Parameters,
) -> Result<(), FamilyError> {
    if is_text_field(field) {
        return Ok(());
    }
    match value {
        toml::Value::String(s) => {
            if let Some(expression) = expression_of(s) {
                let x = evaluate(expression, parameters).map_err(|message| FamilyError {
                    field: field.to_owned(),
                    message: format!("expression `{}`: {message}", echo(s)),
                })?;
                *value = number_value(x);
            }
        }
        toml::Value::Array(items) => {
            for (i, item) in items.iter_mut().enumerate() {
                evaluate_value(item, &format!("{field}[{i}]"), parameters)?;
            }
        }
        toml::Value::Table(table) => {
            for (key, item) in table.iter_mut() {
                evaluate_value(item, &format!("{field}.{key}"), parameters)?;
            }
        }
        _ => {}
    }
    Ok(())
}

/// Whole numbers become TOML integers (so `knots = "= 5 * cycles"` works), others floats.
fn number_value(x: f64) -> toml::Value {
    if x.fract() == 0.0 && x.abs() < 2f64.powi(53) {
        toml::Value::Integer(x as i64)
    } else {
        toml::Value::Float(x)
    }
}

fn is_identifier(s: &str) -> bool {
    let mut chars = s.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// Evaluates an arithmetic expression over `parameters`; the error says what and where.
pub fn evaluate(expression: &str, parameters: &Parameters) -> Result<f64, String> {
    let tokens = tokenize(expression)?;
    let mut parser = Parser {
        tokens: &tokens,
        at: 0,
        depth: 0,
        parameters,
    };
    let x = parser.sum()?;
    if let Some(t) = parser.tokens.get(parser.at) {
        return Err(format!("unexpected `{}`", t.text()));
    }
    if !x.is_finite() {
        return Err(format!(
            "the result is {x} (division by zero?); the values were {}",
            describe(parameters)
        ));
    }
    Ok(x)
}

fn describe(parameters: &Parameters) -> String {
    if parameters.is_empty() {
        return "no parameters".into();
    }
    parameters
        .iter()
        .map(|(k, v)| format!("{k} = {v}"))
        .collect::<Vec<_>>()
        .join(", ")
}

#[derive(Debug, Clone, PartialEq)]
enum Token {
    Number(f64),
    Name(String),
    Op(char),
}

impl Token {
    fn text(&self) -> String {
        match self {
            Token::Number(x) => x.to_string(),
            Token::Name(n) => n.clone(),
            Token::Op(c) => c.to_string(),
        }
    }
}

fn tokenize(s: &str) -> Result<Vec<Token>, String> {
    let chars: Vec<char> = s.chars().collect();
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        if c.is_whitespace() {
            i += 1;
        } else if "+-*/()".contains(c) {
            tokens.push(Token::Op(c));
            i += 1;
        } else if c.is_ascii_digit() || c == '.' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            // An exponent: e or E, an optional sign, digits.
            if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    while j < chars.len() && chars[j].is_ascii_digit() {
                        j += 1;
                    }
                    i = j;
                }
            }
            let text: String = chars[start..i].iter().collect();
            let x = text
                .parse::<f64>()
                .map_err(|_| format!("`{text}` is not a number"))?;
            tokens.push(Token::Number(x));
        } else if c.is_ascii_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            tokens.push(Token::Name(chars[start..i].iter().collect()));
        } else {
            return Err(format!(
                "unexpected character `{c}`; an expression holds numbers, parameter names, \
                 + - * / and parentheses"
            ));
        }
    }
    if tokens.is_empty() {
        return Err("the expression after `=` is empty".into());
    }
    Ok(tokens)
}

/// A function an expression may call.
type Function = fn(f64) -> f64;

/// The functions an expression may call, of an angle in degrees (exact at multiples of 90°:
/// `sind(180)` is 0, not 1.2e-16).
const FUNCTIONS: [(&str, Function); 3] = [
    ("sind", |d| crate::contact::sin_cos_degrees(d).0),
    ("cosd", |d| crate::contact::sin_cos_degrees(d).1),
    ("tand", |d| {
        let (s, c) = crate::contact::sin_cos_degrees(d);
        s / c
    }),
];

/// Recursive descent: sum := product (('+'|'-') product)*, product := unary (('*'|'/')
/// unary)*, unary := '-' unary | atom, atom := number | name | function '(' sum ')' |
/// '(' sum ')'.
struct Parser<'a> {
    tokens: &'a [Token],
    at: usize,
    /// Open parentheses and unary signs around the current token.
    depth: usize,
    parameters: &'a Parameters,
}

impl Parser<'_> {
    /// One level deeper (a `(` or a unary sign), refused beyond [`MAX_NESTING`].
    fn deeper(&mut self) -> Result<(), String> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            return Err(format!(
                "it nests parentheses and signs more than {MAX_NESTING} deep; write it flatter"
            ));
        }
        Ok(())
    }

    fn peek_op(&self) -> Option<char> {
        match self.tokens.get(self.at) {
            Some(Token::Op(c)) => Some(*c),
            _ => None,
        }
    }

    fn sum(&mut self) -> Result<f64, String> {
        let mut x = self.product()?;
        while let Some(op @ ('+' | '-')) = self.peek_op() {
            self.at += 1;
            let y = self.product()?;
            x = if op == '+' { x + y } else { x - y };
        }
        Ok(x)
    }

    fn product(&mut self) -> Result<f64, String> {
        let mut x = self.unary()?;
        while let Some(op @ ('*' | '/')) = self.peek_op() {
            self.at += 1;
            let y = self.unary()?;
            x = if op == '*' { x * y } else { x / y };
        }
        Ok(x)
    }

    fn unary(&mut self) -> Result<f64, String> {
        match self.peek_op() {
            Some(sign @ ('-' | '+')) => {
                self.at += 1;
                self.deeper()?;
                let x = self.unary()?;
                self.depth -= 1;
                Ok(if sign == '-' { -x } else { x })
            }
            _ => self.atom(),
        }
    }

    fn atom(&mut self) -> Result<f64, String> {
        let token = self
            .tokens
            .get(self.at)
            .ok_or("the expression ends early")?;
        self.at += 1;
        match token {
            Token::Number(x) => Ok(*x),
            Token::Name(name) if matches!(self.tokens.get(self.at), Some(Token::Op('('))) => {
                let f = FUNCTIONS
                    .iter()
                    .find(|(n, _)| n == name)
                    .map(|(_, f)| f)
                    .ok_or_else(|| {
                        let names: Vec<&str> = FUNCTIONS.iter().map(|(n, _)| *n).collect();
                        format!(
                            "unknown function `{name}`; the functions are {}",
                            names.join(", ")
                        )
                    })?;
                self.at += 1;
                self.closed_sum().map(f)
            }
            Token::Name(name) => self.parameters.get(name).copied().ok_or_else(|| {
                let hint = nearest(name, self.parameters.keys().map(String::as_str))
                    .map(|s| format!(", did you mean `{s}`?"))
                    .unwrap_or_default();
                let declared = if self.parameters.is_empty() {
                    "the file declares none (add a [parameters] table)".to_owned()
                } else {
                    format!(
                        "declared: {}",
                        self.parameters
                            .keys()
                            .cloned()
                            .collect::<Vec<_>>()
                            .join(", ")
                    )
                };
                format!("unknown parameter `{name}`{hint}; {declared}")
            }),
            Token::Op('(') => self.closed_sum(),
            Token::Op(c) => Err(format!("unexpected `{c}`")),
        }
    }

    /// The sum after a `(` (already read) and its `)`.
    fn closed_sum(&mut self) -> Result<f64, String> {
        self.deeper()?;
        let x = self.sum()?;
        self.depth -= 1;
        match self.tokens.get(self.at) {
            Some(Token::Op(')')) => {
                self.at += 1;
                Ok(x)
            }
            _ => Err("a `(` is not closed".into()),
        }
    }
}

/// The names of the `[parameters]` a problem file declares, in order (empty when it
/// declares none or cannot be read): what an unknown override key may have meant.
pub fn declared_parameters(file: &std::path::Path) -> Vec<String> {
    crate::files::input::read_regular_text(file, crate::files::input::MAX_TEXT_BYTES)
        .ok()
        .and_then(|text| toml::from_str::<toml::Table>(&text).ok())
        .and_then(|mut t| match t.remove(PARAMETERS) {
            Some(toml::Value::Table(p)) => Some(p.keys().cloned().collect()),
            _ => None,
        })
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params() -> Parameters {
        [("stride_hz".to_owned(), 10.0), ("mu".to_owned(), 0.5)]
            .into_iter()
            .collect()
    }

    #[test]
    fn expressions_follow_arithmetic_precedence() {
        let p = params();
        assert_eq!(evaluate("1/stride_hz * 0.9", &p).unwrap(), 1.0 / 10.0 * 0.9);
        assert_eq!(evaluate("2 + 3 * 4", &p).unwrap(), 14.0);
        assert_eq!(evaluate("(2 + 3) * 4", &p).unwrap(), 20.0);
        assert_eq!(evaluate("-mu - -1", &p).unwrap(), 0.5);
        assert_eq!(evaluate("8 / 4 / 2", &p).unwrap(), 1.0);
        assert_eq!(evaluate("1e-3 * 2.5E2", &p).unwrap(), 0.25);
    }

    /// sind, cosd and tand take degrees, exactly at multiples of 90°, and nest.
    #[test]
    fn expressions_call_trigonometric_functions_of_degrees() {
        let p = params();
        assert_eq!(evaluate("sind(90)", &p).unwrap(), 1.0);
        assert_eq!(evaluate("cosd(90)", &p).unwrap(), 0.0);
        assert_eq!(evaluate("sind(-180)", &p).unwrap(), 0.0);
        assert!((evaluate("sind(30)", &p).unwrap() - 0.5).abs() < 1e-15);
        assert!((evaluate("2 * tand(45 * mu * 2)", &p).unwrap() - 2.0).abs() < 1e-15);
        assert!((evaluate("cosd(sind(90) * 60)", &p).unwrap() - 0.5).abs() < 1e-15);
        let e = evaluate("sin(30)", &p).unwrap_err();
        assert!(
            e.contains("unknown function `sin`") && e.contains("sind"),
            "{e}"
        );
        assert!(evaluate("sind(30", &p).unwrap_err().contains("not closed"));
    }

    #[test]
    fn bad_expressions_say_why() {
        let p = params();
        let e = evaluate("1/strid_hz", &p).unwrap_err();
        assert!(e.contains("unknown parameter `strid_hz`"), "{e}");
        assert!(e.contains("did you mean `stride_hz`"), "{e}");
        let e = evaluate("1/(stride_hz - 10)", &p).unwrap_err();
        assert!(e.contains("inf") && e.contains("stride_hz = 10"), "{e}");
        assert!(evaluate("2 ^ 3", &p).unwrap_err().contains("character `^`"));
        assert!(evaluate("(1 + 2", &p).unwrap_err().contains("not closed"));
        assert!(evaluate("1 2", &p).unwrap_err().contains("unexpected `2`"));
        assert!(evaluate("  ", &p).unwrap_err().contains("empty"));
        assert!(evaluate("1 +", &p).unwrap_err().contains("ends early"));
    }

    #[test]
    fn tables_are_rewritten_and_named_on_error() {
        let mut root: toml::Table = toml::from_str(
            "[parameters]\nhz = 4\n[horizon]\nknots = \"= 2 * hz + 1\"\n\
             total_time = [\"= 0.9 / hz\", \"= 1.1/hz\"]\nname = \"plain\"\n",
        )
        .unwrap();
        let p = take_parameters(&mut root).unwrap();
        assert!(has_expressions(&root));
        evaluate_expressions(&mut root, &p).unwrap();
        let h = root["horizon"].as_table().unwrap();
        assert_eq!(h["knots"], toml::Value::Integer(9));
        assert_eq!(h["total_time"][0], toml::Value::Float(0.9 / 4.0));
        assert_eq!(h["name"], toml::Value::String("plain".into()));
        assert!(!root.contains_key(PARAMETERS));

        let mut root: toml::Table =
            toml::from_str("[horizon]\ntotal_time = [1, \"= 1/hz\"]\n").unwrap();
        let e = evaluate_expressions(&mut root, &Parameters::new()).unwrap_err();
        assert_eq!(e.field, "horizon.total_time[1]");
        assert!(e.message.contains("declares none"), "{}", e.message);

        for (text, fragment) in [
            ("[parameters]\nhz = \"ten\"\n", "must be a number"),
            ("[parameters]\nhz = nan\n", "not a finite number"),
            ("slack = 1\n[parameters]\nslack = 1\n", "ambiguous"),
            ("parameters = 3\n", "table of numbers"),
        ] {
            let mut root: toml::Table = toml::from_str(text).unwrap();
            let e = take_parameters(&mut root).unwrap_err();
            assert!(e.message.contains(fragment), "{text}: {}", e.message);
        }
    }
}
