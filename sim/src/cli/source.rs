//! Scenario files named on the command line: folders expand to their `*.toml` files, sorted.

use std::path::{Path, PathBuf};

use crate::scenario::{DEFAULT_ROOM_ORIGIN, DEFAULT_ROOM_TOML, Scenario};
use anyhow::{Context, bail};

/// A loaded scenario with the file it came from (its text is attached to recordings).
pub struct Source {
    /// The file's name ("kakiuchi-room.toml").
    pub file: String,
    /// The file's text.
    pub text: String,
    /// The parsed, validated scenario.
    pub scenario: Scenario,
}

impl Source {
    /// Reads and validates `path`.
    pub fn load(path: &Path) -> anyhow::Result<Self> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read {}", path.display()))?;
        let scenario = Scenario::from_toml_str(&text, &path.display().to_string())?;
        let file = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        Ok(Self {
            file,
            text,
            scenario,
        })
    }

    /// The paper's room, embedded in the binary.
    pub fn default_room() -> anyhow::Result<Self> {
        Ok(Self {
            file: DEFAULT_ROOM_ORIGIN.to_string(),
            text: DEFAULT_ROOM_TOML.to_string(),
            scenario: Scenario::default_room()?,
        })
    }
}

/// The scenario files `args` name: a file as given, a folder as every `*.toml` in it sorted by name.
/// A path that does not exist, or a folder with no scenario, is an error.
pub fn expand(args: &[PathBuf]) -> anyhow::Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for arg in args {
        if arg.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(arg)
                .with_context(|| format!("cannot list {}", arg.display()))?
                .filter_map(|entry| entry.ok().map(|e| e.path()))
                .filter(|p| p.is_file() && p.extension().is_some_and(|e| e == "toml"))
                .collect();
            if found.is_empty() {
                bail!("{} holds no scenario files (*.toml)", arg.display());
            }
            found.sort();
            files.extend(found);
        } else if arg.exists() {
            files.push(arg.clone());
        } else {
            bail!("{}: no such file or folder", arg.display());
        }
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folder_expands_to_its_toml_files_in_name_order() {
        // Invariant: folders give their *.toml files sorted by name, other files are ignored, and missing paths are errors.
        let dir = tempfile::tempdir().expect("temp dir");
        for name in ["b.toml", "a.toml", "notes.txt"] {
            std::fs::write(dir.path().join(name), "").expect("write");
        }
        let files = expand(&[dir.path().to_path_buf()]).expect("expands");
        let names: Vec<_> = files
            .iter()
            .filter_map(|p| p.file_name()?.to_str())
            .collect();
        assert_eq!(names, ["a.toml", "b.toml"]);
        let missing = expand(&[dir.path().join("nope.toml")]).expect_err("missing file");
        assert!(missing.to_string().contains("no such file"), "{missing}");
        let empty = tempfile::tempdir().expect("temp dir");
        assert!(expand(&[empty.path().to_path_buf()]).is_err());
    }
}
