//! From byte offsets to places a person can find: field paths, lines and columns.
//!
//! The public types stay plain (no `Spanned<>`), so a second, span-keeping parse of the same text
//! (`toml::de::DeTable`) answers "where is `object[2].mass`?" and "which field holds byte 312?".

use std::ops::Range;

use nudge_robot_model::text_place::line_column;
use toml::Spanned;
use toml::de::{DeTable, DeValue};

use super::error::{FieldPath, InvalidScenario, PathSegment, ScenarioFault};
use super::validate::Violation;

/// The document parsed with spans.
pub(super) type SpannedDoc<'i> = Spanned<DeTable<'i>>;

/// Turns a deserialiser error (syntax, unknown or missing field, wrong type) into a located fault.
pub(super) fn from_toml_error(
    text: &str,
    origin: &str,
    error: &toml::de::Error,
) -> InvalidScenario {
    let span = error.span().unwrap_or(0..0);
    let message = error.message().trim().to_owned();
    let (field, fault) = match DeTable::parse(text) {
        Err(_) => (FieldPath::root(), ScenarioFault::Syntax { message }),
        Ok(doc) => {
            if let Some(name) = quoted_after(&message, "missing field `") {
                let table = table_with_span(&doc, &span).unwrap_or_default();
                (table.key(&name), ScenarioFault::MissingField { name })
            } else if let Some(name) = quoted_after(&message, "unknown field `") {
                (field_at(&doc, &span), ScenarioFault::UnknownField { name })
            } else {
                (field_at(&doc, &span), ScenarioFault::WrongType { message })
            }
        }
    };
    place(text, origin, span.start, field, fault)
}

/// Places a broken range rule at its field's value in the text (or its nearest written ancestor when the
/// field was left to its default).
pub(super) fn from_violation(text: &str, origin: &str, violation: Violation) -> InvalidScenario {
    let offset = match DeTable::parse(text) {
        Ok(doc) => span_of(&doc, &violation.field).start,
        Err(_) => 0, // cannot happen: the text deserialised, so it parses
    };
    place(text, origin, offset, violation.field, violation.fault)
}

fn place(
    text: &str,
    origin: &str,
    offset: usize,
    field: FieldPath,
    fault: ScenarioFault,
) -> InvalidScenario {
    let (line, column) = line_column(text, offset);
    InvalidScenario {
        origin: origin.to_owned(),
        line,
        column,
        field,
        fault,
    }
}

/// The text between `prefix` and the next backtick, e.g. the name in "missing field `mass`".
fn quoted_after(message: &str, prefix: &str) -> Option<String> {
    let rest = message.strip_prefix(prefix)?;
    rest.split('`').next().map(str::to_owned)
}

/// Every key and value of the document with its path and span.
fn nodes(doc: &SpannedDoc<'_>) -> Vec<(FieldPath, Range<usize>)> {
    let mut out = Vec::new();
    collect_table(doc.get_ref(), &FieldPath::root(), &mut out);
    out
}

fn collect_table(table: &DeTable<'_>, path: &FieldPath, out: &mut Vec<(FieldPath, Range<usize>)>) {
    for (key, value) in table.iter() {
        let here = path.key(key.get_ref());
        out.push((here.clone(), key.span()));
        collect_value(value, &here, out);
    }
}

fn collect_value(
    value: &Spanned<DeValue<'_>>,
    path: &FieldPath,
    out: &mut Vec<(FieldPath, Range<usize>)>,
) {
    out.push((path.clone(), value.span()));
    match value.get_ref() {
        DeValue::Table(table) => collect_table(table, path, out),
        DeValue::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                collect_value(item, &path.index(i), out);
            }
        }
        _ => {}
    }
}

/// The field whose key or value has exactly `span`, else the smallest one containing its start.
fn field_at(doc: &SpannedDoc<'_>, span: &Range<usize>) -> FieldPath {
    let nodes = nodes(doc);
    if let Some((path, _)) = nodes.iter().find(|(_, s)| s == span) {
        return path.clone();
    }
    nodes
        .into_iter()
        .filter(|(_, s)| s.start <= span.start && span.start < s.end)
        .min_by_key(|(_, s)| s.end - s.start)
        .map(|(path, _)| path)
        .unwrap_or_default()
}

/// The table whose header (or inline braces) has exactly `span`: where a missing field was expected.
fn table_with_span(doc: &SpannedDoc<'_>, span: &Range<usize>) -> Option<FieldPath> {
    let mut found = None;
    find_table(doc.get_ref(), &FieldPath::root(), span, &mut found);
    found
}

fn find_table(
    table: &DeTable<'_>,
    path: &FieldPath,
    span: &Range<usize>,
    found: &mut Option<FieldPath>,
) {
    for (key, value) in table.iter() {
        find_in_value(value, &path.key(key.get_ref()), span, found);
    }
}

fn find_in_value(
    value: &Spanned<DeValue<'_>>,
    path: &FieldPath,
    span: &Range<usize>,
    found: &mut Option<FieldPath>,
) {
    match value.get_ref() {
        DeValue::Table(table) => {
            if &value.span() == span {
                *found = Some(path.clone());
            }
            find_table(table, path, span, found);
        }
        DeValue::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                find_in_value(item, &path.index(i), span, found);
            }
        }
        _ => {}
    }
}

/// Span of the value at `path`, or of its deepest ancestor present in the text.
fn span_of(doc: &SpannedDoc<'_>, path: &FieldPath) -> Range<usize> {
    let mut span = 0..0;
    let mut current: Option<&Spanned<DeValue<'_>>> = None;
    let mut table: Option<&DeTable<'_>> = Some(doc.get_ref());
    for segment in path.segments() {
        let next = match (segment, table, current.map(Spanned::get_ref)) {
            (PathSegment::Key(key), Some(t), _) => t.get(key.as_str()),
            (PathSegment::Index(i), _, Some(DeValue::Array(items))) => items.get(*i),
            _ => None,
        };
        let Some(value) = next else { break };
        span = value.span();
        current = Some(value);
        table = value.get_ref().as_table();
    }
    span
}

/// Fixed-length arrays of the format, by path with indices written `[]`. serde reads `[f64; 2]` from the
/// first two entries and ignores the rest, so a third entry is caught here rather than silently dropped.
const FIXED_LENGTHS: [(&str, usize); 15] = [
    ("room.size", 2),
    ("room.floor_colour", 3),
    ("room.wall_colour", 3),
    ("robot.start", 3),
    ("goal.position", 2),
    ("object[].position", 2),
    ("object[].colour", 3),
    ("actor[].waypoints[]", 2),
    ("robot.model.head.pan_limits", 2),
    ("robot.model.head.tilt_limits", 2),
    ("robot.model.arm.reach_x", 2),
    ("robot.model.arm.reach_y", 2),
    ("robot.model.arm.reach_z", 2),
    ("robot.model.arm.rest", 3),
    ("robot.model.arm.hand_half", 3),
];

/// The first fixed-length array in the text with extra entries (too few are already refused by serde).
pub(super) fn check_fixed_lengths(text: &str) -> Result<(), Violation> {
    let Ok(doc) = DeTable::parse(text) else {
        return Ok(()); // cannot happen: the text deserialised, so it parses
    };
    let mut arrays = Vec::new();
    collect_arrays(doc.get_ref(), &FieldPath::root(), &mut arrays);
    for (path, got) in arrays {
        let pattern = path_pattern(&path);
        if let Some(&(_, expected)) = FIXED_LENGTHS.iter().find(|(p, _)| *p == pattern)
            && got > expected
        {
            return Err(Violation {
                field: path,
                fault: ScenarioFault::ArrayLength { expected, got },
            });
        }
    }
    Ok(())
}

/// Every array in the document with its length, in document order of keys.
fn collect_arrays(table: &DeTable<'_>, path: &FieldPath, out: &mut Vec<(FieldPath, usize)>) {
    for (key, value) in table.iter() {
        collect_arrays_in(value.get_ref(), &path.key(key.get_ref()), out);
    }
}

fn collect_arrays_in(value: &DeValue<'_>, path: &FieldPath, out: &mut Vec<(FieldPath, usize)>) {
    match value {
        DeValue::Table(table) => collect_arrays(table, path, out),
        DeValue::Array(items) => {
            out.push((path.clone(), items.len()));
            for (i, item) in items.iter().enumerate() {
                collect_arrays_in(item.get_ref(), &path.index(i), out);
            }
        }
        _ => {}
    }
}

/// `object[3].position` → `object[].position`.
fn path_pattern(path: &FieldPath) -> String {
    let mut pattern = String::new();
    for (i, segment) in path.segments().iter().enumerate() {
        match segment {
            PathSegment::Key(key) if i == 0 => pattern.push_str(key),
            PathSegment::Key(key) => {
                pattern.push('.');
                pattern.push_str(key);
            }
            PathSegment::Index(_) => pattern.push_str("[]"),
        }
    }
    pattern
}
