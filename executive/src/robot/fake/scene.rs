//! The fake robot's scripted world: boxes standing on a floor, each answering a push as scripted.
//!
//! No physics: a guarded move's line is cast against the boxes once, when it starts, and the first
//! box it meets answers it as its [`ObjectResponse`] says. A box that gives way moves with the hand
//! along the line; nothing else moves it. The camera sees the boxes where they are now
//! ([`super::render`]), so colour ICP measures what the script did.

use nalgebra::{Isometry2, Point2, Translation2, Vector2, Vector3};
use nudge_perception::Rgb;

use super::ObjectResponse;
use super::render::FakeCamera;

/// A box standing on the floor (its bottom at z = 0), and how it answers a push.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneBox {
    /// Name, for the tests' ground truth.
    pub name: String,
    /// Pose of the footprint's centre (map frame).
    pub pose: Isometry2<f64>,
    /// Size along the box's own x and y, and its height (m).
    pub size: Vector3<f64>,
    /// Base colour; faces carry a texture bound to the box, so it moves with the box.
    pub colour: Rgb,
    /// How it answers a push.
    pub response: ObjectResponse,
    /// How far pushes have moved it so far (m).
    pub moved: f64,
}

impl SceneBox {
    /// A box of `size` (x, y, height; m) centred at `(x, y)` with yaw `yaw` (rad).
    pub fn new(
        name: &str,
        (x, y, yaw): (f64, f64, f64),
        size: Vector3<f64>,
        colour: Rgb,
        response: ObjectResponse,
    ) -> Self {
        Self {
            name: name.to_string(),
            pose: Isometry2::new(Vector2::new(x, y), yaw),
            size,
            colour,
            response,
            moved: 0.0,
        }
    }

    /// Where a ray from `from` along the unit `dir` (map frame, at height `z`) enters the footprint:
    /// its distance along the ray (0 when `from` is inside), or `None` when it misses or passes
    /// above or below the box.
    pub fn entry(&self, from: &Point2<f64>, dir: &Vector2<f64>, z: f64) -> Option<f64> {
        if !(0.0..=self.size.z).contains(&z) {
            return None;
        }
        let o = self.pose.inverse_transform_point(from);
        let d = self.pose.rotation.inverse_transform_vector(dir);
        let half = [self.size.x / 2.0, self.size.y / 2.0];
        let (mut near, mut far) = (f64::NEG_INFINITY, f64::INFINITY);
        for axis in 0..2 {
            let (o, d, h) = (o[axis], d[axis], half[axis]);
            if d.abs() < 1e-12 {
                if o.abs() > h {
                    return None;
                }
                continue;
            }
            let (a, b) = ((-h - o) / d, (h - o) / d);
            near = near.max(a.min(b));
            far = far.min(a.max(b));
        }
        // A line from inside the box touches it at once, unless it leaves the box within a press's
        // depth: a hand withdrawing from a face it pressed pulls nothing.
        let withdrawing = near < 0.0 && far <= PRESSED_IN;
        (near <= far && far >= 0.0 && !withdrawing).then_some(near.max(0.0))
    }

    /// Moves the box by `offset` (map frame, m), counting the distance as pushed.
    pub fn shift(&mut self, offset: &Vector2<f64>) {
        self.pose = Translation2::from(*offset) * self.pose;
        self.moved += offset.norm();
    }
}

/// How deep (m) inside a box's face a hand that pressed it may lie: ten times the press a stiff box
/// allows at the 20 N limit (20 kN/m: 1 mm), far less than any box is deep.
const PRESSED_IN: f64 = 0.01;

/// The fake robot's world: a floor and boxes, seen by one camera.
#[derive(Clone, Debug, PartialEq)]
pub struct FakeScene {
    /// Floor colour, with a faint texture bound to the map.
    pub floor: Rgb,
    /// Everything standing on the floor: walls, furniture.
    pub boxes: Vec<SceneBox>,
    /// The head's range camera.
    pub camera: FakeCamera,
}

impl FakeScene {
    /// An empty floor of colour `floor`, seen by the default camera.
    pub fn new(floor: Rgb) -> Self {
        Self {
            floor,
            boxes: Vec::new(),
            camera: FakeCamera::default(),
        }
    }

    /// Adds `item`.
    pub fn with(mut self, item: SceneBox) -> Self {
        self.boxes.push(item);
        self
    }

    /// Adds four static walls, `thickness` thick and `height` high, around the rectangle from `min`
    /// to `max` (their inner faces on its edges).
    pub fn with_walls(
        self,
        min: Point2<f64>,
        max: Point2<f64>,
        height: f64,
        thickness: f64,
        colour: Rgb,
    ) -> Self {
        let (w, h, t) = (max.x - min.x, max.y - min.y, thickness);
        let (cx, cy) = ((min.x + max.x) / 2.0, (min.y + max.y) / 2.0);
        let wall = |name: &str, x: f64, y: f64, sx: f64, sy: f64| {
            SceneBox::new(
                name,
                (x, y, 0.0),
                Vector3::new(sx, sy, height),
                colour,
                ObjectResponse::RIGID,
            )
        };
        self.with(wall("wall-south", cx, min.y - t / 2.0, w + 2.0 * t, t))
            .with(wall("wall-north", cx, max.y + t / 2.0, w + 2.0 * t, t))
            .with(wall("wall-west", min.x - t / 2.0, cy, t, h))
            .with(wall("wall-east", max.x + t / 2.0, cy, t, h))
    }

    /// The box called `name`.
    pub fn get(&self, name: &str) -> Option<&SceneBox> {
        self.boxes.iter().find(|b| b.name == name)
    }

    /// The first box a hand moving from `from` along the unit `dir` (map frame, at height `z`) meets,
    /// and how far along the line it meets it.
    pub fn first_hit(
        &self,
        from: &Point2<f64>,
        dir: &Vector2<f64>,
        z: f64,
    ) -> Option<(usize, f64)> {
        self.boxes
            .iter()
            .enumerate()
            .filter_map(|(i, b)| b.entry(from, dir, z).map(|t| (i, t)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robot::fake::ObjectResponse;

    #[test]
    fn a_hand_line_touches_a_box_heading_into_it_not_leaving_the_face_it_pressed() {
        // Invariant: a line from outside meets the box's near face where it enters; one from a millimetre inside the near face touches it at once when it heads in, and misses it when it heads back out (a hand withdrawing from a face it pressed pulls nothing).
        let b = SceneBox::new(
            "box",
            (1.0, 0.0, 0.0),
            Vector3::new(0.4, 0.6, 0.8),
            [200, 60, 60],
            ObjectResponse::RIGID,
        );
        let forward = Vector2::new(1.0, 0.0);
        let entry = b
            .entry(&Point2::new(0.0, 0.0), &forward, 0.5)
            .expect("meets it");
        assert!((entry - 0.8).abs() < 1e-12, "{entry}");
        let pressed = Point2::new(0.801, 0.0);
        assert_eq!(b.entry(&pressed, &forward, 0.5), Some(0.0));
        assert_eq!(b.entry(&pressed, &-forward, 0.5), None);
    }
}
