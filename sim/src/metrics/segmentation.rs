//! Segmentation scored against the simulation's truth: how well the obstacles of one look-around
//! match the objects that returned its points.
//!
//! Every return of the look carries the owner of the surface it came from (the sensor's own rays,
//! traced without noise: [`crate::adapter::SimRobot::owners`]). For each scenario object `o` that the
//! look saw, its *main obstacle* `M(o)` is the obstacle holding most of its returns, and
//!
//! - **completeness** = (returns of `o` in `M(o)`) / (returns of `o`): 1 when the object is one
//!   obstacle, ½ when it was cut in two halves;
//! - **purity** = (returns of `o` in `M(o)`) / (returns in `M(o)`): 1 when nothing else is in its
//!   obstacle, ½ when it was merged with a wall as large as itself.
//!
//! Both count only returns above the floor band perception labels as low (`low_height`, 5 cm): the
//! bottom centimetres of every object meet the floor, which perception takes away by design. An
//! object counts as seen with at least [`MIN_RETURNS`] returns in that band. The room's structure is
//! scored apart from the things a push test and a clearing push work on: objects as tall as the
//! room's walls (partitions, joined to the walls they meet and cut with them into convex runs) or
//! longer than the robot pushes.

use std::collections::HashMap;

use nalgebra::Isometry2;
use nudge_executive::robot::{ActionStatus, Clock, Head, RangeCamera};
use nudge_perception::{ColourCloud, PerceptionConfig, Prism, fuse};

use crate::adapter::SimRobot;
use crate::scenario::Scenario;
use crate::surface::Owner;

/// Fewest returns above the floor band for an object to count as seen: a 10 × 10 pixel patch,
/// about 9 cm across at 2 m, the least a push test's colour ICP is given to align.
pub const MIN_RETURNS: usize = 100;

/// How one seen object came out of the segmentation.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectScore {
    /// The scenario object's name.
    pub name: String,
    /// Its returns above the floor band.
    pub returns: usize,
    /// Share of its returns in its main obstacle.
    pub completeness: f64,
    /// Share of its main obstacle's returns that are its own.
    pub purity: f64,
    /// Whether it is a thing to push rather than the room's structure: lower than the room's walls
    /// and no longer than the executive's largest candidate.
    pub pushable: bool,
}

/// One look-around's clouds, the owner of each of their pixels, and the base pose it was taken from.
pub struct LabelledLook {
    /// The views, in the sensor frame with their poses.
    pub views: Vec<ColourCloud>,
    /// Per view, the owner of each pixel's surface.
    pub owners: Vec<Vec<Option<Owner>>>,
    /// Where the base stood.
    pub base: Isometry2<f64>,
}

/// Takes a look-around (the views of `config`) from where `robot` stands, with the owners of its
/// pixels.
pub fn labelled_look(
    robot: &mut SimRobot,
    config: &PerceptionConfig,
) -> Result<LabelledLook, nudge_executive::robot::RobotError> {
    let mut views = Vec::new();
    let mut owners = Vec::new();
    for view in config.look_around.views() {
        robot.start_point_head(view.pan_rad(), view.tilt_rad())?;
        while robot.head_status()? == ActionStatus::Running {
            robot.advance(0.05)?;
        }
        owners.push(robot.owners());
        views.push(robot.capture()?);
    }
    let base = nudge_executive::robot::Base::base_pose(robot)?.value;
    Ok(LabelledLook {
        views,
        owners,
        base,
    })
}

/// Scores `prisms`, detected from `look`, against the owners of its returns. `low_height` is the
/// floor band left out (m above the floor at z = 0), `longest_push` the largest object the robot
/// pushes (m).
pub fn score_look(
    look: &LabelledLook,
    prisms: &[Prism],
    scenario: &Scenario,
    low_height: f32,
    longest_push: f64,
) -> Vec<ObjectScore> {
    // The fused cloud keeps the views' finite slots in order: their owners, in the same order.
    let fused = fuse(&look.views);
    let owners = look.views.iter().zip(&look.owners).flat_map(|(v, o)| {
        let (xs, ys, zs) = (v.xs(), v.ys(), v.zs());
        (0..xs.len())
            .filter(move |&i| xs[i].is_finite() && ys[i].is_finite() && zs[i].is_finite())
            .map(move |i| o.get(i).copied().flatten())
    });
    let key = |p: &nalgebra::Point3<f32>| (p.x.to_bits(), p.y.to_bits(), p.z.to_bits());
    let mut owner_of: HashMap<(u32, u32, u32), Option<Owner>> = HashMap::new();
    let mut seen: HashMap<usize, usize> = HashMap::new();
    for ((_, p, _), owner) in fused.iter_valid().zip(owners) {
        owner_of.insert(key(&p), owner);
        if p.z > low_height
            && let Some(Owner::Object(i)) = owner
        {
            *seen.entry(i).or_default() += 1;
        }
    }
    // Per obstacle: its returns above the band, and how many each object gave.
    let tallies: Vec<(usize, HashMap<usize, usize>)> = prisms
        .iter()
        .map(|prism| {
            let mut total = 0;
            let mut by_object: HashMap<usize, usize> = HashMap::new();
            for (_, p, _) in prism
                .points
                .iter_valid()
                .filter(|(_, p, _)| p.z > low_height)
            {
                total += 1;
                if let Some(Some(Owner::Object(i))) = owner_of.get(&key(&p)) {
                    *by_object.entry(*i).or_default() += 1;
                }
            }
            (total, by_object)
        })
        .collect();
    let mut scores = Vec::new();
    for (i, spec) in scenario.objects.iter().enumerate() {
        let returns = seen.get(&i).copied().unwrap_or(0);
        if returns < MIN_RETURNS {
            continue;
        }
        let (own, total) = tallies
            .iter()
            .map(|(total, by)| (by.get(&i).copied().unwrap_or(0), *total))
            .max_by_key(|(own, _)| *own)
            .unwrap_or((0, 0));
        let (longest, height) = match spec.kind {
            crate::scenario::ObjectKind::Cylinder => (spec.size[0], spec.size[1]),
            _ => (spec.size[0].max(spec.size[1]), spec.size[2]),
        };
        scores.push(ObjectScore {
            name: spec.name.clone(),
            returns,
            completeness: own as f64 / returns as f64,
            purity: if total == 0 {
                0.0
            } else {
                own as f64 / total as f64
            },
            pushable: longest <= longest_push
                && spec.elevation + height < scenario.room.wall_height,
        });
    }
    scores
}
