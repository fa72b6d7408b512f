//! Where a byte of a text is, as a person finds it: the line and column every nudge TOML reader
//! (scenarios, robot descriptions, ROS 2 configurations) puts in its errors.

/// 1-based line and column (in characters) of a byte offset; offsets past the end land after the last
/// character, offsets inside a character at its start.
pub fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line_start = before.rfind('\n').map_or(0, |nl| nl + 1);
    (
        before.matches('\n').count() + 1,
        before[line_start..].chars().count() + 1,
    )
}
