//! `--set key.path=value` overrides: parsed from the command line, applied to the problem
//! file's TOML table before it is checked.

#![warn(missing_docs)]

use crate::problem::ProblemError;

/// A `--set key.path=value` override, as given and as parsed.
#[derive(Debug, Clone, PartialEq)]
pub struct Override {
    /// TOML path, e.g. `slack.weight` or `cost[0].time_weighted`.
    pub path: String,
    /// The value as a TOML value (a bare word that is not TOML becomes a string).
    pub value: toml::Value,
}

impl Override {
    /// Parses `key.path=value`.
    pub fn parse(arg: &str) -> Result<Override, ProblemError> {
        let err = |message: &str| ProblemError::Override {
            arg: crate::problem::family::echo(arg),
            message: message.to_owned(),
        };
        let (path, raw) = arg
            .split_once('=')
            .ok_or_else(|| err("expected key.path=value"))?;
        let path = path.trim();
        if path.is_empty() {
            return Err(err("the key path is empty"));
        }
        if path.split('.').count() > crate::problem::family::MAX_NESTING {
            return Err(err(&format!(
                "the key path has more than {} parts",
                crate::problem::family::MAX_NESTING
            )));
        }
        let raw = raw.trim();
        if raw.contains(['\n', '\r']) {
            return Err(err(
                "the value holds a line break: one --set sets one value (give each key its own --set)",
            ));
        }
        let value = match toml::from_str::<toml::Table>(&format!("v = {raw}")) {
            Ok(mut t) => t.remove("v").ok_or_else(|| err("no value"))?,
            Err(_) => toml::Value::String(raw.to_owned()),
        };
        if matches!(value, toml::Value::Table(_)) {
            return Err(err("only scalar and array values can be set"));
        }
        Ok(Override {
            path: path.to_owned(),
            value,
        })
    }

    pub(super) fn apply(&self, root: &mut toml::Table) -> Result<(), ProblemError> {
        let err = |message: String| ProblemError::Override {
            arg: format!("{}={}", self.path, self.value),
            message,
        };
        let parts: Vec<&str> = self.path.split('.').collect();
        let mut table = root;
        for (i, part) in parts.iter().enumerate() {
            let (key, index) = match part.split_once('[') {
                Some((k, rest)) => {
                    let idx: usize = rest
                        .trim_end_matches(']')
                        .parse()
                        .map_err(|_| err(format!("bad index in `{part}`")))?;
                    (k, Some(idx))
                }
                None => (*part, None),
            };
            let last = i + 1 == parts.len();
            match (index, last) {
                (None, true) => {
                    table.insert(key.to_owned(), self.value.clone());
                    return Ok(());
                }
                (None, false) => {
                    let entry = table
                        .entry(key.to_owned())
                        .or_insert_with(|| toml::Value::Table(toml::Table::new()));
                    table = entry
                        .as_table_mut()
                        .ok_or_else(|| err(format!("`{key}` is not a table")))?;
                }
                (Some(idx), _) => {
                    let array = table
                        .get_mut(key)
                        .and_then(|v| v.as_array_mut())
                        .ok_or_else(|| err(format!("`{key}` is not an array in the file")))?;
                    let len = array.len();
                    let element = array.get_mut(idx).ok_or_else(|| {
                        err(format!(
                            "`{key}` has {len} elements, index {idx} is out of range"
                        ))
                    })?;
                    if last {
                        *element = self.value.clone();
                        return Ok(());
                    }
                    table = element
                        .as_table_mut()
                        .ok_or_else(|| err(format!("`{key}[{idx}]` is not a table")))?;
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn override_parses_toml_values_and_bare_words() {
        let o = Override::parse("slack.weight=1e3").unwrap();
        assert_eq!(o.path, "slack.weight");
        assert_eq!(o.value, toml::Value::Float(1000.0));
        let o = Override::parse("robot.base=planar").unwrap();
        assert_eq!(o.value, toml::Value::String("planar".into()));
        let o = Override::parse("horizon.total_time=[1, 2.5]").unwrap();
        assert!(o.value.is_array());
        assert!(Override::parse("no_equals_sign").is_err());
        assert!(Override::parse("a={b=1}").is_err());
    }
}
