//! Reading a robot description: TOML into the types, then the range rules, every fault placed in the
//! text (`origin:line:column: field: message`).

use std::ops::Range;
use std::path::Path;

use toml::Spanned;
use toml::de::{DeTable, DeValue};

use crate::error::{InvalidModel, ModelError};
use crate::model::RobotModel;
use crate::text_place::line_column;

/// Fixed-length arrays of the format: serde takes a `[f64; 2]` from the first two entries of a longer
/// array and drops the rest, so a third entry is caught here rather than silently ignored.
const FIXED_LENGTHS: [(&str, &str, usize); 7] = [
    ("head", "pan_limits", 2),
    ("head", "tilt_limits", 2),
    ("arm", "reach_x", 2),
    ("arm", "reach_y", 2),
    ("arm", "reach_z", 2),
    ("arm", "rest", 3),
    ("arm", "hand_half", 3),
];

impl RobotModel {
    /// Parses and checks a robot description; `origin` (a path or a name) starts every error. Fields
    /// left out keep the paper's robot's values.
    ///
    /// ```
    /// use nudge_robot_model::RobotModel;
    /// let model = RobotModel::from_toml_str("[head]\nheight = 1.2\n", "small.toml").expect("valid");
    /// assert_eq!(model.head.height, 1.2);
    /// assert_eq!(model.camera.width, 176);
    ///
    /// let error = RobotModel::from_toml_str("[arm]\nreach_x = [0.8, 0.2]\n", "bad.toml")
    ///     .expect_err("reach backwards");
    /// assert_eq!(error.to_string(), "bad.toml:2:17: arm.reach_x[1]: must be finite and above 0.8, got 0.2");
    /// ```
    pub fn from_toml_str(text: &str, origin: &str) -> Result<RobotModel, ModelError> {
        let invalid = |offset: usize, field: String, message: String| {
            let (line, column) = line_column(text, offset);
            ModelError::Invalid(Box::new(InvalidModel {
                origin: origin.to_owned(),
                line,
                column,
                field,
                message,
            }))
        };
        let model: RobotModel = toml::from_str(text).map_err(|e| {
            let span = e.span().unwrap_or(0..0);
            invalid(span.start, String::new(), e.message().trim().to_owned())
        })?;
        // It deserialised, so it parses.
        let doc = DeTable::parse(text).map_err(|e| invalid(0, String::new(), e.to_string()))?;
        for (table, key, length) in FIXED_LENGTHS {
            if let Some(value) = lookup(&doc, table, key)
                && let DeValue::Array(items) = value.get_ref()
                && items.len() != length
            {
                return Err(invalid(
                    value.span().start,
                    format!("{table}.{key}"),
                    format!("must hold {length} numbers, got {}", items.len()),
                ));
            }
        }
        model
            .validate()
            .map_err(|v| invalid(span_of(&doc, &v.field).start, v.field, v.message))?;
        Ok(model)
    }

    /// Reads and checks a robot description file; errors name the path as given.
    pub fn from_path(path: &Path) -> Result<RobotModel, ModelError> {
        let text = std::fs::read_to_string(path).map_err(|source| ModelError::Io {
            path: path.to_owned(),
            source,
        })?;
        Self::from_toml_str(&text, &path.display().to_string())
    }
}

fn lookup<'a, 'i>(
    doc: &'a Spanned<DeTable<'i>>,
    table: &str,
    key: &str,
) -> Option<&'a Spanned<DeValue<'i>>> {
    doc.get_ref().get(table)?.get_ref().as_table()?.get(key)
}

/// Span of the value at `field` (`arm.reach_x[1]`), or of its deepest ancestor written in the text.
fn span_of(doc: &Spanned<DeTable<'_>>, field: &str) -> Range<usize> {
    let mut span = 0..0;
    let mut table = Some(doc.get_ref());
    for part in field.split('.') {
        let (key, index) = match part.split_once('[') {
            Some((key, rest)) => (key, rest.trim_end_matches(']').parse::<usize>().ok()),
            None => (part, None),
        };
        let Some(value) = table.and_then(|t| t.get(key)) else {
            break;
        };
        span = value.span();
        table = value.get_ref().as_table();
        if let Some(i) = index {
            let DeValue::Array(items) = value.get_ref() else {
                break;
            };
            let Some(item) = items.get(i) else { break };
            span = item.span();
        }
    }
    span
}

#[cfg(test)]
mod tests {
    use super::*;

    fn error(text: &str) -> String {
        RobotModel::from_toml_str(text, "robot.toml")
            .expect_err("invalid")
            .to_string()
    }

    #[test]
    fn an_empty_description_is_the_papers_robot() {
        // Invariant: every field left out keeps the paper's value, so an empty file is HRP-2 with its SR-4000.
        let model = RobotModel::from_toml_str("", "empty.toml").expect("valid");
        assert_eq!(model, RobotModel::default());
        assert!(RobotModel::default().validate().is_ok());
    }

    #[test]
    fn faults_are_placed_at_their_field() {
        // Invariant: a bad value, an unknown field, a wrong type, a long fixed array and broken syntax each name the file, the line and column, and (where there is one) the field.
        assert_eq!(
            error("[body]\nradius = -0.3\n"),
            "robot.toml:2:10: body.radius: must be positive, got -0.3"
        );
        assert!(
            error("[camera]\nwidht = 10\n").starts_with("robot.toml:2:1: unknown field `widht`"),
            "{}",
            error("[camera]\nwidht = 10\n")
        );
        assert!(error("[head]\nheight = \"tall\"\n").starts_with("robot.toml:2:10: "));
        assert_eq!(
            error("[arm]\nrest = [0.2, 0.1, 0.8, 9.0]\n"),
            "robot.toml:2:8: arm.rest: must hold 3 numbers, got 4"
        );
        assert!(error("[arm\n").starts_with("robot.toml:1:"));
        assert_eq!(
            error("[force]\ncontact_threshold = 25.0\n"),
            "robot.toml:1:1: force.test_limit: must be finite and above force.contact_threshold, got 20"
        );
    }

    #[test]
    fn a_missing_file_names_its_path() {
        // Invariant: a file that cannot be read is an error naming it, never a panic.
        let e = RobotModel::from_path(Path::new("/nonexistent/robot.toml")).expect_err("missing");
        assert!(
            e.to_string()
                .starts_with("/nonexistent/robot.toml: cannot read"),
            "{e}"
        );
    }
}
