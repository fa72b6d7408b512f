//! What can be wrong with a scenario file, and where.

use std::fmt;
use std::path::PathBuf;

use super::ObjectKind;

/// A scenario could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum ScenarioError {
    /// The file could not be read.
    #[error("{}: cannot read the scenario file: {source}", path.display())]
    Io {
        /// The file that was asked for.
        path: PathBuf,
        /// Why reading failed.
        #[source]
        source: std::io::Error,
    },
    /// The text is not a valid scenario; boxed to keep `Result<Scenario, _>` small.
    #[error(transparent)]
    Invalid(Box<InvalidScenario>),
}

impl ScenarioError {
    /// The located fault, unless the file could not be read at all.
    pub fn invalid(&self) -> Option<&InvalidScenario> {
        match self {
            Self::Io { .. } => None,
            Self::Invalid(invalid) => Some(invalid),
        }
    }
}

impl From<InvalidScenario> for ScenarioError {
    fn from(invalid: InvalidScenario) -> Self {
        Self::Invalid(Box::new(invalid))
    }
}

/// A fault in a scenario text with its place: `origin:line:column: field: fault`.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct InvalidScenario {
    /// Where the text came from: a file path, or a name such as `kakiuchi-room.toml`.
    pub origin: String,
    /// 1-based line of the offending key or value.
    pub line: usize,
    /// 1-based column (in characters) of the offending key or value.
    pub column: usize,
    /// Path of the offending field, e.g. `object[2].mass`; empty for faults of the whole text.
    pub field: FieldPath,
    /// What is wrong.
    pub fault: ScenarioFault,
}

impl InvalidScenario {
    /// Whether this fault's place lies inside `text`, the text it was found in: its line exists and
    /// its column falls on that line or just past its end. `Err` says how it misses. A fault that
    /// points outside its text sends a user to the wrong place; the loader's fuzz tests hold it to this.
    pub fn place_within(&self, text: &str) -> Result<(), String> {
        let line = text
            .split('\n')
            .nth(self.line.wrapping_sub(1))
            .ok_or_else(|| format!("line {} of {}: {self}", self.line, text.split('\n').count()))?;
        let width = line.chars().count() + 1;
        if self.column == 0 || self.column > width {
            return Err(format!(
                "column {} on a line {width} wide: {self}",
                self.column
            ));
        }
        Ok(())
    }
}

impl fmt::Display for InvalidScenario {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}: ", self.origin, self.line, self.column)?;
        if !self.field.is_empty() {
            write!(f, "{}: ", self.field)?;
        }
        write!(f, "{}", self.fault)
    }
}

/// One step of a [`FieldPath`].
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum PathSegment {
    /// A table key, as written in the file (`object`, `mass`).
    Key(String),
    /// A 0-based position in an array (also in an array of tables such as `[[object]]`).
    Index(usize),
}

/// Where a value sits in a scenario file, written `object[2].mass`.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Default)]
pub struct FieldPath(Vec<PathSegment>);

impl FieldPath {
    /// The path of the whole document.
    pub fn root() -> Self {
        Self::default()
    }

    /// This path extended by a table key.
    pub fn key(&self, key: &str) -> Self {
        let mut next = self.clone();
        next.0.push(PathSegment::Key(key.to_owned()));
        next
    }

    /// This path extended by an array index.
    pub fn index(&self, index: usize) -> Self {
        let mut next = self.clone();
        next.0.push(PathSegment::Index(index));
        next
    }

    /// The steps from the document root.
    pub fn segments(&self) -> &[PathSegment] {
        &self.0
    }

    /// True for the whole document.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

impl fmt::Display for FieldPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, segment) in self.0.iter().enumerate() {
            match segment {
                PathSegment::Key(key) if i == 0 => write!(f, "{key}")?,
                PathSegment::Key(key) => write!(f, ".{key}")?,
                PathSegment::Index(index) => write!(f, "[{index}]")?,
            }
        }
        Ok(())
    }
}

/// What is wrong with a scenario, without its place.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ScenarioFault {
    /// A robot description's rule is broken (`[robot.model]`).
    #[error("{message}")]
    RobotModel {
        /// What is wrong, as the description's rule says it.
        message: String,
    },
    /// The text is not TOML.
    #[error("TOML syntax: {message}")]
    Syntax {
        /// The parser's description.
        message: String,
    },
    /// A key the format does not know (often a typo).
    #[error("unknown field `{name}`")]
    UnknownField {
        /// The key as written.
        name: String,
    },
    /// A required key is absent.
    #[error("missing required field `{name}`")]
    MissingField {
        /// The absent key.
        name: String,
    },
    /// A value of the wrong type or outside its type's range (a string for a number, 300 for a colour).
    #[error("wrong type or value: {message}")]
    WrongType {
        /// The deserialiser's description.
        message: String,
    },
    /// A fixed-length array (a position, a colour) with too many entries.
    #[error("needs exactly {expected} entries, got {got}")]
    ArrayLength {
        /// How many entries the field takes.
        expected: usize,
        /// How many were given.
        got: usize,
    },
    /// NaN or infinity.
    #[error("must be a finite number, got {value}")]
    NotFinite {
        /// The value as read.
        value: f64,
    },
    /// Zero or negative where only a positive value makes sense.
    #[error("must be positive, got {value}")]
    NotPositive {
        /// The value as read.
        value: f64,
    },
    /// Negative where zero is allowed.
    #[error("must not be negative, got {value}")]
    Negative {
        /// The value as read.
        value: f64,
    },
    /// Outside a closed interval.
    #[error("must be in [{min}, {max}], got {value}")]
    OutOfRange {
        /// The value as read.
        value: f64,
        /// Smallest allowed value.
        min: f64,
        /// Largest allowed value.
        max: f64,
    },
    /// `size` has the wrong number of entries for the object's kind.
    #[error("a {kind} needs {expected} size entries ({meaning}), got {got}")]
    SizeEntries {
        /// The object's kind.
        kind: ObjectKind,
        /// How many entries the kind needs.
        expected: usize,
        /// What the entries mean.
        meaning: &'static str,
        /// How many were given.
        got: usize,
    },
    /// A room side over the limit.
    #[error("room side of {value} m exceeds the {max} m limit")]
    RoomTooLarge {
        /// The side as read (m).
        value: f64,
        /// The limit (m).
        max: f64,
    },
    /// Too many objects.
    #[error("{count} objects, at most {max} allowed")]
    TooManyObjects {
        /// How many the file has.
        count: usize,
        /// The limit.
        max: usize,
    },
    /// Something that must lie inside the room does not.
    #[error("{what} is outside the {width} m × {depth} m room")]
    OutsideRoom {
        /// What pokes out, e.g. "footprint corner (6.2, 0.3)".
        what: String,
        /// Room extent along x (m).
        width: f64,
        /// Room extent along y (m).
        depth: f64,
    },
    /// The robot's disc at its start overlaps an object.
    #[error("the robot's disc at the start overlaps object `{object}`")]
    StartInsideObject {
        /// The object's name.
        object: String,
    },
    /// The goal point lies inside an object.
    #[error("the goal lies inside object `{object}`")]
    GoalInsideObject {
        /// The object's name.
        object: String,
    },
    /// An actor without waypoints.
    #[error("needs at least one waypoint")]
    NoWaypoints,
    /// Two objects, or two actors, share a name.
    #[error("name `{name}` is already used by {first}")]
    DuplicateName {
        /// The repeated name.
        name: String,
        /// The path of its first use, e.g. `object[1]`.
        first: String,
    },
    /// A reference to an object that does not exist.
    #[error("no object named `{name}`")]
    UnknownObject {
        /// The name as written.
        name: String,
    },
    /// An object carried by two actors.
    #[error("object `{name}` is already carried by actor `{by}`")]
    AlreadyCarried {
        /// The object's name.
        name: String,
        /// The first actor that carries it.
        by: String,
    },
    /// A bolted object cannot be pulled along.
    #[error("object `{name}` is fixed and cannot be carried")]
    CarriedFixed {
        /// The object's name.
        name: String,
    },
    /// `drop_at` or `pick_at` without `carries`.
    #[error("nothing to drop or pick: the actor has no `carries`")]
    NothingCarried,
    /// `pick_at` without a `drop_at`: the object is still in hand.
    #[error("`pick_at` needs a `drop_at`: the object is never left")]
    PickWithoutDrop,
    /// `pick_at` not after `drop_at` on a walk that does not repeat.
    #[error(
        "`pick_at` ({pick_at}) must come after `drop_at` ({drop_at}) on a walk that does not repeat"
    )]
    PickBeforeDrop {
        /// The drop waypoint.
        drop_at: usize,
        /// The pick waypoint.
        pick_at: usize,
    },
    /// A waypoint index past the end of the list.
    #[error("waypoint index {index} is past the last waypoint ({count} waypoints)")]
    IndexPastWaypoints {
        /// The index as read.
        index: usize,
        /// How many waypoints there are.
        count: usize,
    },
    /// `pause` neither empty nor one entry per waypoint.
    #[error("needs 0 or {waypoints} entries (one per waypoint), got {got}")]
    PauseLength {
        /// How many entries were given.
        got: usize,
        /// How many waypoints there are.
        waypoints: usize,
    },
    /// An object expected both movable and static.
    #[error("object `{name}` is expected both movable and static")]
    ContradictoryExpect {
        /// The object's name.
        name: String,
    },
}
