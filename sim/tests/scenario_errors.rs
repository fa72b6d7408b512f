//! Bad scenario files: every one is refused with its field path, line, column and a stable message.

use nudge_sim::scenario::{InvalidScenario, Scenario, ScenarioError, ScenarioFault};

/// A valid scenario whose line numbers the cases below rely on (line N is `BASE.lines().nth(N - 1)`).
const BASE: &str = r#"name = "base"
seed = 7

[room]
size = [6.0, 3.6]
wall_height = 2.0

[robot]
start = [0.6, 1.8, 0.0]
radius = 0.35
height = 1.54
walk_speed = 0.15

[goal]
position = [5.4, 1.8]
tolerance = 0.2

[[object]]
name = "table"
kind = "table"
position = [3.0, 1.8]
yaw = 90.0
size = [1.2, 0.8, 0.72]
mass = 25.0
friction = 0.6
colour = [120, 78, 42]

[[object]]
name = "chair-1"
kind = "chair"
position = [3.8, 0.85]
size = [0.5, 0.5, 0.85]
mass = 4.0
friction = 0.4
colour = [40, 70, 170]

[[object]]
name = "bin"
kind = "cylinder"
position = [1.5, 0.5]
size = [0.4, 0.6]
elevation = 0.0
mass = 3.0
colour = [60, 60, 60]

[[actor]]
name = "person"
waypoints = [[1.0, 3.0], [5.0, 3.0]]
speed = 0.6
pause = [0.0, 2.0]
carries = "bin"
drop_at = 1

[expect]
outcome = "goal"
movable = ["chair-1"]
static = ["table"]
"#;

/// `BASE` with whole lines replaced (1-based line numbers), so every other line keeps its number.
fn with_lines(replacements: &[(usize, &str)]) -> String {
    let mut lines: Vec<String> = BASE.lines().map(str::to_owned).collect();
    for &(line, text) in replacements {
        assert_eq!(
            lines.get(line - 1).map(|l| l.is_empty()),
            Some(false),
            "replacing a blank or missing line {line} would shift nothing but is likely a typo in the case"
        );
        lines[line - 1] = text.to_owned();
    }
    lines.join("\n") + "\n"
}

fn refuse(text: &str) -> InvalidScenario {
    match Scenario::from_toml_str(text, "bad.toml") {
        Ok(_) => panic!("the scenario was accepted:\n{text}"),
        Err(ScenarioError::Io { .. }) => panic!("an io error from a string"),
        Err(ScenarioError::Invalid(invalid)) => *invalid,
    }
}

struct Case {
    what: &'static str,
    text: String,
    field: &'static str,
    line: usize,
    column: usize,
    fragment: &'static str,
}

fn case(
    what: &'static str,
    replacements: &[(usize, &str)],
    field: &'static str,
    (line, column): (usize, usize),
    fragment: &'static str,
) -> Case {
    Case {
        what,
        text: with_lines(replacements),
        field,
        line,
        column,
        fragment,
    }
}

fn cases() -> Vec<Case> {
    vec![
        // Syntax, schema and types.
        case(
            "syntax: two values",
            &[(24, "mass = 25.0 25")],
            "",
            (24, 8),
            "TOML syntax",
        ),
        // The parser notices the missing `]` where the next line starts.
        case(
            "syntax: unclosed array",
            &[(5, "size = [6.0, 3.6")],
            "",
            (6, 1),
            "TOML syntax",
        ),
        case(
            "unknown field",
            &[(42, "elevaton = 0.0")],
            "object[2].elevaton",
            (42, 1),
            "unknown field `elevaton`",
        ),
        case(
            "unknown section",
            &[(14, "[gaol]")],
            "gaol",
            (14, 2),
            "unknown field `gaol`",
        ),
        case(
            "wrong type",
            &[(33, r#"mass = "heavy""#)],
            "object[1].mass",
            (33, 8),
            "wrong type or value",
        ),
        case(
            "colour over 255",
            &[(35, "colour = [40, 300, 170]")],
            "object[1].colour[1]",
            (35, 15),
            "u8",
        ),
        case(
            "unknown kind",
            &[(30, r#"kind = "sofa""#)],
            "object[1].kind",
            (30, 8),
            "unknown variant `sofa`",
        ),
        case(
            "negative seed",
            &[(2, "seed = -1")],
            "seed",
            (2, 8),
            "wrong type or value",
        ),
        case(
            "missing mass",
            &[(33, "# no mass")],
            "object[1].mass",
            (28, 1),
            "missing required field `mass`",
        ),
        case(
            "missing goal",
            &[(14, "# no goal"), (15, "# position"), (16, "# tolerance")],
            "goal",
            (1, 1),
            "missing required field `goal`",
        ),
        case(
            "room side with three entries",
            &[(5, "size = [6.0, 3.6, 2.0]")],
            "room.size",
            (5, 8),
            "needs exactly 2 entries, got 3",
        ),
        case(
            "colour with two entries",
            &[(26, "colour = [120, 78]")],
            "object[0].colour",
            (26, 10),
            "array of length 3",
        ),
        case(
            "waypoint with three numbers",
            &[(48, "waypoints = [[1.0, 3.0, 0.0]]")],
            "actor[0].waypoints[0]",
            (48, 14),
            "needs exactly 2 entries, got 3",
        ),
        // Range rules.
        case(
            "negative room side",
            &[(5, "size = [6.0, -3.6]")],
            "room.size[1]",
            (5, 14),
            "must be positive, got -3.6",
        ),
        case(
            "room too large",
            &[(5, "size = [150.0, 3.6]")],
            "room.size[0]",
            (5, 9),
            "exceeds the 100 m limit",
        ),
        case(
            "zero wall height",
            &[(6, "wall_height = 0.0")],
            "room.wall_height",
            (6, 15),
            "must be positive, got 0",
        ),
        case(
            "negative robot radius",
            &[(10, "radius = -0.35")],
            "robot.radius",
            (10, 10),
            "must be positive, got -0.35",
        ),
        case(
            "zero robot height",
            &[(11, "height = 0.0")],
            "robot.height",
            (11, 10),
            "must be positive",
        ),
        case(
            "zero walk speed",
            &[(12, "walk_speed = 0.0")],
            "robot.walk_speed",
            (12, 14),
            "must be positive, got 0",
        ),
        case(
            "start outside room",
            &[(9, "start = [0.2, 1.8, 0.0]")],
            "robot.start",
            (9, 9),
            "outside the 6 m × 3.6 m room",
        ),
        case(
            "negative goal tolerance",
            &[(16, "tolerance = -0.2")],
            "goal.tolerance",
            (16, 13),
            "must be positive",
        ),
        case(
            "goal outside room",
            &[(15, "position = [6.4, 1.8]")],
            "goal.position",
            (15, 12),
            "the goal (6.4, 1.8) is outside",
        ),
        case(
            "NaN mass",
            &[(24, "mass = nan")],
            "object[0].mass",
            (24, 8),
            "must be a finite number, got NaN",
        ),
        case(
            "infinite position",
            &[(21, "position = [inf, 1.8]")],
            "object[0].position[0]",
            (21, 13),
            "must be a finite number, got inf",
        ),
        case(
            "negative mass",
            &[(33, "mass = -3")],
            "object[1].mass",
            (33, 8),
            "must be positive, got -3",
        ),
        case(
            "zero mass",
            &[(43, "mass = 0.0")],
            "object[2].mass",
            (43, 8),
            "must be positive, got 0",
        ),
        case(
            "cylinder with three size entries",
            &[(41, "size = [0.4, 0.6, 0.5]")],
            "object[2].size",
            (41, 8),
            "a cylinder needs 2 size entries (diameter, height), got 3",
        ),
        case(
            "chair with two size entries",
            &[(32, "size = [0.5, 0.5]")],
            "object[1].size",
            (32, 8),
            "a chair needs 3 size entries",
        ),
        case(
            "zero size entry",
            &[(32, "size = [0.5, 0.0, 0.85]")],
            "object[1].size[1]",
            (32, 14),
            "must be positive, got 0",
        ),
        case(
            "friction over 2",
            &[(34, "friction = 2.5")],
            "object[1].friction",
            (34, 12),
            "must be in [0, 2], got 2.5",
        ),
        case(
            "negative friction",
            &[(25, "friction = -0.1")],
            "object[0].friction",
            (25, 12),
            "must be in [0, 2], got -0.1",
        ),
        case(
            "negative elevation",
            &[(42, "elevation = -0.2")],
            "object[2].elevation",
            (42, 13),
            "must not be negative, got -0.2",
        ),
        case(
            "chair through the wall",
            &[(31, "position = [5.9, 0.85]")],
            "object[1].position",
            (31, 12),
            "footprint corner (6.150, 1.100) is outside",
        ),
        // Turned 90°, the table is 1.2 m deep in y: centred at y 3.2 it pokes 0.2 m through the wall.
        case(
            "turned table through the wall",
            &[(21, "position = [3.0, 3.2]")],
            "object[0].position",
            (21, 12),
            "is outside the 6 m × 3.6 m room",
        ),
        case(
            "start overlaps an object",
            &[(9, "start = [1.5, 0.9, 0.0]")],
            "robot.start",
            (9, 9),
            "overlaps object `bin`",
        ),
        case(
            "goal inside an object",
            &[(15, "position = [3.0, 1.8]")],
            "goal.position",
            (15, 12),
            "inside object `table`",
        ),
        case(
            "duplicate object name",
            &[(38, r#"name = "table""#)],
            "object[2].name",
            (38, 8),
            "name `table` is already used by object[0]",
        ),
        case(
            "empty waypoints",
            &[(48, "waypoints = []")],
            "actor[0].waypoints",
            (48, 13),
            "needs at least one waypoint",
        ),
        case(
            "waypoint outside room",
            &[(48, "waypoints = [[1.0, 3.0], [6.5, 3.0]]")],
            "actor[0].waypoints[1]",
            (48, 26),
            "waypoint (6.5, 3) is outside",
        ),
        case(
            "zero actor speed",
            &[(49, "speed = 0.0")],
            "actor[0].speed",
            (49, 9),
            "must be positive, got 0",
        ),
        case(
            "pause length",
            &[(50, "pause = [1.0]")],
            "actor[0].pause",
            (50, 9),
            "needs 0 or 2 entries (one per waypoint), got 1",
        ),
        case(
            "negative pause",
            &[(50, "pause = [1.0, -2.0]")],
            "actor[0].pause[1]",
            (50, 15),
            "must not be negative",
        ),
        case(
            "carries unknown object",
            &[(51, r#"carries = "trolley""#)],
            "actor[0].carries",
            (51, 11),
            "no object named `trolley`",
        ),
        case(
            "drop_at past waypoints",
            &[(52, "drop_at = 2")],
            "actor[0].drop_at",
            (52, 11),
            "waypoint index 2 is past the last waypoint (2 waypoints)",
        ),
        case(
            "drop_at without carries",
            &[(51, "# carries nothing")],
            "actor[0].drop_at",
            (52, 11),
            "nothing to drop or pick",
        ),
        case(
            "pick_at before drop_at",
            &[(52, "pick_at = 0\ndrop_at = 1")],
            "actor[0].pick_at",
            (52, 11),
            "`pick_at` (0) must come after `drop_at` (1)",
        ),
        case(
            "pick_at without drop_at",
            &[(52, "pick_at = 1")],
            "actor[0].pick_at",
            (52, 11),
            "`pick_at` needs a `drop_at`",
        ),
        case(
            "expect unknown object",
            &[(56, r#"movable = ["chair-9"]"#)],
            "expect.movable[0]",
            (56, 12),
            "no object named `chair-9`",
        ),
        case(
            "expect contradiction",
            &[(57, r#"static = ["chair-1"]"#)],
            "expect.static[0]",
            (57, 11),
            "both movable and static",
        ),
        case(
            "unknown outcome",
            &[(55, r#"outcome = "win""#)],
            "expect.outcome",
            (55, 11),
            "unknown variant `win`",
        ),
    ]
}

#[test]
fn every_bad_file_is_refused_at_its_field_line_and_column() {
    // Invariant: each broken file gives an error naming the offending field path, its line and column,
    // and a stable message fragment; none is accepted and none panics.
    let mut failures = Vec::new();
    let cases = cases();
    assert!(
        cases.len() >= 20,
        "the brief asks for at least 20 distinct bad files"
    );
    for case in &cases {
        let error = match Scenario::from_toml_str(&case.text, "bad.toml") {
            Ok(_) => {
                failures.push(format!("{}: accepted", case.what));
                continue;
            }
            Err(error) => error
                .invalid()
                .cloned()
                .expect("a located fault, not an io error"),
        };
        let got = (error.field.to_string(), error.line, error.column);
        let want = (case.field.to_owned(), case.line, case.column);
        let message = error.to_string();
        if got != want || !message.contains(case.fragment) || !message.starts_with("bad.toml:") {
            failures.push(format!(
                "{}: got {got:?} `{message}`, want {want:?} containing `{}`",
                case.what, case.fragment
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} cases wrong:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

#[test]
fn the_base_file_is_valid() {
    // Invariant: the cases above break exactly one thing; the file they start from loads.
    let scenario = Scenario::from_toml_str(BASE, "base.toml").expect("the base scenario is valid");
    assert_eq!(scenario.objects.len(), 3);
    assert_eq!(scenario.actors[0].drop_at, Some(1));
}

#[test]
fn display_reads_origin_line_column_field_message() {
    // Invariant: the message has the `origin:line:column: field: fault` shape editors and people jump to.
    let error = Scenario::from_toml_str(&with_lines(&[(33, "mass = -3")]), "kakiuchi-room.toml")
        .expect_err("a negative mass is refused");
    assert_eq!(
        error.to_string(),
        "kakiuchi-room.toml:33:8: object[1].mass: must be positive, got -3"
    );
    let invalid = error.invalid().expect("a located fault");
    assert_eq!(invalid.fault, ScenarioFault::NotPositive { value: -3.0 });
}

#[test]
fn a_syntax_error_has_no_field_but_a_place() {
    // Invariant: faults of the whole text omit the field but still give line and column.
    let error = Scenario::from_toml_str(&with_lines(&[(19, "name = table")]), "x.toml")
        .expect_err("bare word");
    let invalid = error.invalid().expect("a located fault");
    assert!(invalid.field.is_empty());
    assert_eq!((invalid.line, invalid.column), (19, 8));
    assert!(
        error.to_string().starts_with("x.toml:19:8: TOML syntax:"),
        "{error}"
    );
}

#[test]
fn a_duplicate_actor_name_is_refused() {
    // Invariant: two actors may not share a name; the second one's name is the culprit.
    let text =
        format!("{BASE}\n[[actor]]\nname = \"person\"\nwaypoints = [[2.0, 2.0]]\nspeed = 0.5\n");
    let error = refuse(&text);
    assert_eq!(
        (error.field.to_string(), error.line, error.column),
        ("actor[1].name".to_owned(), 60, 8)
    );
    assert!(
        error
            .to_string()
            .contains("name `person` is already used by actor[0]"),
        "{error}"
    );
}

#[test]
fn a_carried_object_must_be_loose_and_carried_once() {
    // Invariant: a bolted object cannot be pulled, and two actors cannot pull the same object.
    let fixed = BASE.replace("elevation = 0.0\n", "elevation = 0.0\nfixed = true\n");
    let error = refuse(&fixed);
    assert_eq!(error.field.to_string(), "actor[0].carries");
    assert!(
        error.to_string().contains("object `bin` is fixed"),
        "{error}"
    );

    let twice = format!(
        "{BASE}\n[[actor]]\nname = \"other\"\nwaypoints = [[2.0, 2.0]]\nspeed = 0.5\ncarries = \"bin\"\n"
    );
    let error = refuse(&twice);
    assert_eq!(
        (error.field.to_string(), error.line, error.column),
        ("actor[1].carries".to_owned(), 63, 11)
    );
    assert!(
        error
            .to_string()
            .contains("already carried by actor `person`"),
        "{error}"
    );
}

#[test]
fn more_than_500_objects_are_refused_at_the_501st() {
    // Invariant: the object limit is 500; the error points at the header of the first object too many.
    let mut text = with_lines(&[]);
    let first_new_line = text.lines().count() + 1;
    let per_object = 7;
    for i in 0..497 {
        let (x, y) = (0.1 + 0.01 * (i % 500) as f64, 0.05);
        text.push_str(&format!(
            "[[object]]\nname = \"pebble-{i}\"\nkind = \"box\"\nposition = [{x}, {y}]\nsize = [0.01, 0.01, 0.01]\nmass = 0.01\ncolour = [1, 2, 3]\n"
        ));
    }
    Scenario::from_toml_str(&text, "many.toml").expect("500 objects are allowed");
    text.push_str("[[object]]\nname = \"one-too-many\"\nkind = \"box\"\nposition = [5.0, 0.05]\nsize = [0.01, 0.01, 0.01]\nmass = 0.01\ncolour = [1, 2, 3]\n");
    let error = refuse(&text);
    assert_eq!(error.field.to_string(), "object[500]");
    assert_eq!(
        (error.line, error.column),
        (first_new_line + 497 * per_object, 1)
    );
    assert!(
        error
            .to_string()
            .contains("501 objects, at most 500 allowed"),
        "{error}"
    );
}

#[test]
fn mats_and_overhead_objects_do_not_block_start_or_goal() {
    // Invariant: the robot may start on a mat and under a high shelf, and its goal may lie on a mat.
    let text = format!(
        "{BASE}\n[[object]]\nname = \"rug\"\nkind = \"mat\"\nposition = [0.6, 1.8]\nsize = [0.8, 0.8, 0.01]\nmass = 1.0\ncolour = [200, 0, 0]\n\
         \n[[object]]\nname = \"shelf\"\nkind = \"box\"\nposition = [0.6, 1.8]\nsize = [0.5, 0.5, 0.1]\nelevation = 1.6\nmass = 5.0\ncolour = [9, 9, 9]\n\
         \n[[object]]\nname = \"goal-rug\"\nkind = \"mat\"\nposition = [5.4, 1.8]\nsize = [0.8, 0.8, 0.01]\nmass = 1.0\ncolour = [0, 200, 0]\n"
    );
    Scenario::from_toml_str(&text, "mats.toml")
        .expect("mats and overhead objects are not obstacles here");
    // The same shelf at 1.2 m, below the robot's 1.54 m, does block the start.
    let low = text.replace("elevation = 1.6", "elevation = 1.2");
    let error = refuse(&low);
    assert_eq!(error.field.to_string(), "robot.start");
    assert!(
        error.to_string().contains("overlaps object `shelf`"),
        "{error}"
    );
}

#[test]
fn a_missing_file_is_an_io_error_naming_the_path() {
    // Invariant: an unreadable file gives the io variant, and its message names the path.
    let path = std::path::Path::new("/nonexistent/nudge/room.toml");
    let error = Scenario::from_path(path).expect_err("the file does not exist");
    assert!(matches!(error, ScenarioError::Io { .. }));
    assert!(
        error
            .to_string()
            .starts_with("/nonexistent/nudge/room.toml: cannot read"),
        "{error}"
    );
}

#[test]
fn columns_count_characters_not_bytes() {
    // Invariant: a column is the character position a person sees, even after multi-byte characters.
    let line = r#"object = [{ name = "Stühle-ü", kind = "chair", position = [1.0, 1.0], size = [0.5, 0.5, 0.8], mass = -3.0, colour = [1, 2, 3] }]"#;
    let text = format!(
        "{line}\nname = \"inline\"\n[room]\nsize = [6.0, 3.6]\n[robot]\nstart = [0.6, 1.8, 0.0]\n[goal]\nposition = [5.4, 1.8]\n"
    );
    let error = refuse(&text);
    let byte_column = line.find("-3.0").expect("the mass") + 1;
    let char_column = line[..byte_column - 1].chars().count() + 1;
    assert_ne!(byte_column, char_column);
    assert_eq!(
        (error.field.to_string(), error.line, error.column),
        ("object[0].mass".to_owned(), 1, char_column)
    );
}
