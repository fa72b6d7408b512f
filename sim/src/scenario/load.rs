//! Reading scenario text: TOML into the types, then the range rules, every fault placed in the text.

use std::path::Path;

use super::Scenario;
use super::error::ScenarioError;
use super::locate::{check_fixed_lengths, from_toml_error, from_violation};

/// The paper's room, embedded so the binary runs without any file.
pub const DEFAULT_ROOM_TOML: &str = include_str!("../../../scenarios/kakiuchi-room.toml");
/// The name errors in [`DEFAULT_ROOM_TOML`] would carry.
pub const DEFAULT_ROOM_ORIGIN: &str = "kakiuchi-room.toml";

impl Scenario {
    /// Parses and validates scenario text; `origin` (a path or a name) starts every error message.
    ///
    /// ```
    /// use nudge_sim::scenario::Scenario;
    /// let text = "name = \"tiny\"\n[room]\nsize = [4.0, 3.0]\n[robot]\nstart = [0.5, 1.5, 0.0]\n\
    ///             [goal]\nposition = [3.5, 1.5]\n";
    /// let scenario = Scenario::from_toml_str(text, "tiny.toml").expect("a valid scenario");
    /// assert_eq!(scenario.room.wall_height, 2.0);
    ///
    /// let bad = text.replace("[4.0, 3.0]", "[4.0, -3.0]");
    /// let error = Scenario::from_toml_str(&bad, "tiny.toml").expect_err("a negative room side");
    /// assert_eq!(error.to_string(), "tiny.toml:3:14: room.size[1]: must be positive, got -3");
    /// ```
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Scenario, ScenarioError> {
        let scenario: Scenario =
            toml::from_str(text).map_err(|e| from_toml_error(text, origin, &e))?;
        check_fixed_lengths(text)
            .and_then(|()| scenario.validate())
            .map_err(|violation| from_violation(text, origin, violation))?;
        Ok(scenario)
    }

    /// Reads, parses and validates a scenario file; errors name the path as given.
    pub fn from_path(path: &Path) -> Result<Scenario, ScenarioError> {
        let text = std::fs::read_to_string(path).map_err(|source| ScenarioError::Io {
            path: path.to_owned(),
            source,
        })?;
        Self::from_toml_str(&text, &path.display().to_string())
    }

    /// The paper's room (`scenarios/kakiuchi-room.toml`, embedded at build time). A test loads it, so in a
    /// tested build this is always `Ok`.
    pub fn default_room() -> Result<Scenario, ScenarioError> {
        Self::from_toml_str(DEFAULT_ROOM_TOML, DEFAULT_ROOM_ORIGIN)
    }
}
