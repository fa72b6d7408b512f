//! Families of generated scenarios (`nudge generate`): rooms nobody tuned for, each with an `[expect]`
//! block that is right by construction. A family draws a room from its seeded generator, states what
//! it guarantees ([`Guarantee`]), and the draw is kept only when the guarantee holds in the true world
//! ([`Guarantee::holds`], on the ideal path of `crate::metrics::ideal_path`): the expectation is checked
//! against ground truth, never assumed. Same family, seed and index: the same file, bit for bit.

mod families;
mod furniture;
pub mod pushable;

use std::fmt;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use crate::metrics::ideal_path::ideal_path_length;
use crate::scenario::{Expect, ExpectedOutcome, Scenario};
use crate::world::{World, WorldError};

pub use families::Family;
pub use pushable::{NeededPush, PushKind, PushMade, check_pushes};

/// Draws per scenario before a family gives up. A draw fails when its random layout breaks the
/// family's guarantee (pieces that happen to shut the way) or the loader refuses it; that is the
/// exception, so running out of 200 means a broken family, not bad luck.
const DRAWS: usize = 200;

/// What a generated scenario promises about its true world.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Guarantee {
    /// A way to the goal exists once every movable object is taken away.
    WayExists,
    /// A way exists with the movable objects taken away, and none while this movable object stays
    /// where it is (bolted in place): the robot must move it. Expected: goal, it movable.
    WayNeeds(String),
    /// A way exists with the movable objects taken away, and none while any one of these movable
    /// objects stays where it is (two boxes abreast in a doorway, each alone leaving less than the
    /// robot's width): the robot must move every one. Expected: goal, each movable.
    WayNeedsEach(Vec<String>),
    /// No way exists even with every movable object taken away, and one would without this static
    /// object: it shuts the goal off. Expected: no path, it static.
    ShutBy(String),
}

impl Guarantee {
    /// The `[expect]` block the guarantee implies.
    pub fn expect(&self) -> Expect {
        match self {
            Self::WayExists => Expect {
                outcome: ExpectedOutcome::Goal,
                movable: Vec::new(),
                static_: Vec::new(),
            },
            Self::WayNeeds(name) => Expect {
                outcome: ExpectedOutcome::Goal,
                movable: vec![name.clone()],
                static_: Vec::new(),
            },
            Self::WayNeedsEach(names) => Expect {
                outcome: ExpectedOutcome::Goal,
                movable: names.clone(),
                static_: Vec::new(),
            },
            Self::ShutBy(name) => Expect {
                outcome: ExpectedOutcome::NoPath,
                movable: Vec::new(),
                static_: vec![name.clone()],
            },
        }
    }

    /// Whether the guarantee holds in `scenario`'s true world.
    pub fn holds(&self, scenario: &Scenario) -> Result<bool, WorldError> {
        Ok(match self {
            Self::WayExists => ideal(scenario)?.is_some(),
            Self::WayNeeds(name) => {
                ideal(scenario)?.is_some()
                    && ideal(&with_object(scenario, name, Change::Bolt))?.is_none()
            }
            Self::WayNeedsEach(names) => {
                if ideal(scenario)?.is_none() {
                    return Ok(false);
                }
                for name in names {
                    if ideal(&with_object(scenario, name, Change::Bolt))?.is_some() {
                        return Ok(false);
                    }
                }
                true
            }
            Self::ShutBy(name) => {
                ideal(scenario)?.is_none()
                    && ideal(&with_object(scenario, name, Change::Remove))?.is_some()
            }
        })
    }
}

impl fmt::Display for Guarantee {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::WayExists => write!(
                f,
                "a way to the goal exists once every movable object is moved"
            ),
            Self::WayNeeds(n) => write!(
                f,
                "a way exists only once the movable object `{n}` is moved"
            ),
            Self::WayNeedsEach(names) => write!(
                f,
                "a way exists only once each of the movable objects `{}` is moved",
                names.join("`, `")
            ),
            Self::ShutBy(n) => write!(
                f,
                "the static object `{n}` shuts the goal off: no way exists"
            ),
        }
    }
}

/// One generated scenario and what it guarantees.
#[derive(Clone, Debug, PartialEq)]
pub struct Generated {
    /// The scenario, its `[expect]` block and family filled in.
    pub scenario: Scenario,
    /// What its true world guarantees.
    pub guarantee: Guarantee,
    /// The pushes it needs the robot to make, each checked on the true world (empty for a family
    /// that names none).
    pub pushes: Vec<PushMade>,
}

/// Why a family could not generate.
#[derive(Debug, thiserror::Error)]
pub enum GenerateError {
    /// A drawn world could not be built (a family's bug).
    #[error("{family} #{index}: {source}")]
    World {
        /// The family.
        family: Family,
        /// The scenario's index.
        index: usize,
        /// What the world said.
        source: WorldError,
    },
    /// No draw met the family's guarantee.
    #[error("{family} #{index}: no draw of {DRAWS} met its guarantee")]
    NoDraw {
        /// The family.
        family: Family,
        /// The scenario's index.
        index: usize,
    },
}

/// Scenario `index` of `family` from generator seed `seed`: drawn from a generator seeded by all
/// three, so one scenario does not depend on how many others are made.
pub fn generate_one(family: Family, seed: u64, index: usize) -> Result<Generated, GenerateError> {
    let mut rng = ChaCha8Rng::seed_from_u64(
        seed ^ (family as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ (index as u64).rotate_left(32),
    );
    for _ in 0..DRAWS {
        let (mut scenario, guarantee, needs) = family.draw(&mut rng);
        scenario.name = format!("{}-{index:03}", family.name());
        scenario.family = Some(family.name().to_string());
        scenario.description = format!("{}: {guarantee}.", family.summary());
        scenario.seed = index as u64 + 1;
        scenario.expect = Some(guarantee.expect());
        tidy(&mut scenario);
        // Only what the scenario loader accepts is written: a draw it refuses is drawn again.
        let written = to_toml(&Generated {
            scenario: scenario.clone(),
            guarantee: guarantee.clone(),
            pushes: Vec::new(),
        });
        if !written.is_ok_and(|text| Scenario::from_toml_str(&text, "generated").is_ok()) {
            continue;
        }
        let holds = guarantee
            .holds(&scenario)
            .map_err(|source| GenerateError::World {
                family,
                index,
                source,
            })?;
        if !holds {
            continue;
        }
        let world_error = |source| GenerateError::World {
            family,
            index,
            source,
        };
        if let Some(pushes) = check_pushes(&scenario, &needs).map_err(world_error)? {
            return Ok(Generated {
                scenario,
                guarantee,
                pushes,
            });
        }
    }
    Err(GenerateError::NoDraw { family, index })
}

/// Scenarios `0..count` of `family`.
pub fn generate(family: Family, seed: u64, count: usize) -> Result<Vec<Generated>, GenerateError> {
    (0..count).map(|i| generate_one(family, seed, i)).collect()
}

/// The scenario as a TOML file, headed by comments that say what it is, guarantees and needs.
pub fn to_toml(generated: &Generated) -> Result<String, toml::ser::Error> {
    let body = toml::to_string(&generated.scenario)?;
    let needs: String = generated
        .pushes
        .iter()
        .map(|p| {
            let [dx, dy] = p.push.direction;
            let what = match p.push.kind {
                PushKind::Clear => format!("pushed {:.2} m", p.distance),
                PushKind::Test => "push-tested".to_string(),
            };
            format!(
                "# Needs: `{}` {what} along ({dx:.2}, {dy:.2}), the robot standing at ({:.2}, {:.2}).\n",
                p.push.object, p.stand[0], p.stand[1]
            )
        })
        .collect();
    Ok(format!(
        "# Generated by `nudge generate`: family {}.\n# Guarantee: {}.\n{needs}{body}",
        generated.scenario.family.as_deref().unwrap_or("-"),
        generated.guarantee
    ))
}

/// Rounds what a draw left long (sizes, masses, frictions) so files read well and a file read back
/// is the scenario that was checked: millimetres, tens of grams, friction to 1e-4 (μ m g within
/// 0.01 N of the drawn force for the heaviest box).
fn tidy(scenario: &mut Scenario) {
    // Dividing by the power of ten (not multiplying by its inverse) gives the double nearest the
    // decimal, which TOML then writes as typed.
    let round = |v: f64, per_unit: f64| (v * per_unit).round() / per_unit;
    for o in &mut scenario.objects {
        // Millimetres: a partition between two centimetre marks has its centre on a half centimetre.
        for v in o.position.iter_mut().chain(o.size.iter_mut()) {
            *v = round(*v, 1000.0);
        }
        o.elevation = round(o.elevation, 1000.0);
        o.mass = round(o.mass, 100.0);
        o.friction = round(o.friction, 1.0e4);
    }
}

/// The ideal path's length in `scenario`'s true world at its start.
fn ideal(scenario: &Scenario) -> Result<Option<f64>, WorldError> {
    let world = World::new(scenario, scenario.seed)?;
    let [x, y, _] = scenario.robot.start;
    let goal = nalgebra::Point2::new(scenario.goal.position[0], scenario.goal.position[1]);
    Ok(ideal_path_length(
        &world,
        nalgebra::Point2::new(x, y),
        goal,
        scenario.goal.tolerance,
        scenario.robot.radius(),
    ))
}

enum Change {
    Bolt,
    Remove,
}

/// A copy of `scenario` with object `name` bolted down or taken away.
fn with_object(scenario: &Scenario, name: &str, change: Change) -> Scenario {
    let mut s = scenario.clone();
    match change {
        Change::Bolt => {
            for o in s.objects.iter_mut().filter(|o| o.name == name) {
                o.fixed = true;
            }
        }
        Change::Remove => s.objects.retain(|o| o.name != name),
    }
    s
}
