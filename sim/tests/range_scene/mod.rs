//! Small rapier scenes for the colour range sensor tests: boxes with known colours, built directly
//! with rapier so the tests do not depend on the world builder.
#![allow(dead_code)]

use std::collections::HashMap;

use nalgebra::{Isometry3, Translation3, UnitQuaternion};
use nudge_perception::ColourCloud;
use nudge_sim::scenario::Texture;
use nudge_sim::sensors::colour_range::{ColourRangeSensor, SensorScene};
use nudge_sim::surface::{Owner, Surface};
use rapier3d::prelude::*;

/// Texture seed every test scene uses.
pub const TEXTURE_SEED: u64 = 11;

/// A rapier world and what each of its colliders looks like.
pub struct TestScene {
    pub world: PhysicsWorld,
    surfaces: HashMap<ColliderHandle, Surface>,
}

impl TestScene {
    /// An empty scene (no floor).
    pub fn empty() -> Self {
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::new(0.0, 0.0, -9.81);
        Self {
            world,
            surfaces: HashMap::new(),
        }
    }

    /// A scene with a 10 m × 10 m floor whose top is z = 0.
    pub fn with_floor() -> Self {
        let mut scene = Self::empty();
        scene.add_box(
            RigidBodyType::Fixed,
            [0.0, 0.0, -0.05],
            [5.0, 5.0, 0.05],
            [150, 150, 140],
            Owner::Floor,
        );
        scene
    }

    /// Adds a plain box of half extents `half` centred at `centre`; returns its body and collider.
    pub fn add_box(
        &mut self,
        body_type: RigidBodyType,
        centre: [f32; 3],
        half: [f32; 3],
        colour: [u8; 3],
        owner: Owner,
    ) -> (RigidBodyHandle, ColliderHandle) {
        self.add_textured_box(body_type, centre, half, colour, Texture::Plain, owner)
    }

    /// Adds a box with a texture; returns its body and collider.
    pub fn add_textured_box(
        &mut self,
        body_type: RigidBodyType,
        centre: [f32; 3],
        half: [f32; 3],
        colour: [u8; 3],
        texture: Texture,
        owner: Owner,
    ) -> (RigidBodyHandle, ColliderHandle) {
        let body = RigidBodyBuilder::new(body_type)
            .translation(Vector::new(centre[0], centre[1], centre[2]))
            .build();
        let (b, c) = self
            .world
            .insert(body, ColliderBuilder::cuboid(half[0], half[1], half[2]));
        self.surfaces
            .insert(c, Surface::new(colour, texture, owner));
        (b, c)
    }

    /// Adds a fixed plain box turned by `yaw` about z.
    pub fn add_rotated_box(&mut self, centre: [f32; 3], half: [f32; 3], yaw: f32, colour: [u8; 3]) {
        let body = RigidBodyBuilder::fixed()
            .translation(Vector::new(centre[0], centre[1], centre[2]))
            .rotation(Vector::new(0.0, 0.0, yaw))
            .build();
        let (_, c) = self
            .world
            .insert(body, ColliderBuilder::cuboid(half[0], half[1], half[2]));
        self.surfaces
            .insert(c, Surface::new(colour, Texture::Stripes, Owner::Object(1)));
    }

    /// Adds a table as one compound collider: a 4 cm top of half extents `half` at `height` on four
    /// 5 cm legs, footprint centred at `centre`.
    pub fn add_table(&mut self, centre: [f32; 2], half: [f32; 2], height: f32, colour: [u8; 3]) {
        let cuboid = |c: [f32; 3], h: [f32; 3]| {
            (
                Pose::from_translation(Vector::new(c[0], c[1], c[2])),
                SharedShape::cuboid(h[0], h[1], h[2]),
            )
        };
        let mut parts = vec![cuboid([0.0, 0.0, height - 0.02], [half[0], half[1], 0.02])];
        for sx in [-1.0, 1.0] {
            for sy in [-1.0, 1.0] {
                parts.push(cuboid(
                    [
                        sx * (half[0] - 0.025),
                        sy * (half[1] - 0.025),
                        (height - 0.04) / 2.0,
                    ],
                    [0.025, 0.025, (height - 0.04) / 2.0],
                ));
            }
        }
        let body = RigidBodyBuilder::dynamic()
            .translation(Vector::new(centre[0], centre[1], 0.0))
            .build();
        let (_, c) = self.world.insert(body, ColliderBuilder::compound(parts));
        self.surfaces
            .insert(c, Surface::new(colour, Texture::Checker, Owner::Object(2)));
    }

    /// Brings the broad phase up to date with the colliders, as the sensor requires.
    pub fn refresh(&mut self) {
        self.world.detect_collisions(&(), &());
    }

    /// One frame from `pose`, excluding `exclude`.
    pub fn capture(
        &self,
        sensor: &ColourRangeSensor,
        pose: &Isometry3<f64>,
        frame_seed: u64,
        exclude: Option<RigidBodyHandle>,
    ) -> ColourCloud {
        let lookup = |h: ColliderHandle| self.surfaces.get(&h).copied();
        let scene = SensorScene {
            bodies: &self.world.bodies,
            colliders: &self.world.colliders,
            broad_phase: &self.world.broad_phase,
            surface: &lookup,
            texture_seed: TEXTURE_SEED,
            exclude,
        };
        sensor.capture(&scene, pose, 0.5, frame_seed)
    }
}

/// A sensor pose at `position` with yaw (about z) and pitch (about y, positive looks down).
pub fn pose(position: [f64; 3], yaw: f64, pitch: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(position[0], position[1], position[2]),
        UnitQuaternion::from_euler_angles(0.0, pitch, yaw),
    )
}

/// The measured range (distance from the sensor) of slot `i`, or `None` for a lost return.
pub fn range_of(cloud: &ColourCloud, i: usize) -> Option<f64> {
    cloud.point(i).map(|p| f64::from(p.coords.norm()))
}

/// The bit patterns of a cloud's coordinates and its colours, for bit-for-bit comparison.
pub fn fingerprint(cloud: &ColourCloud) -> (Vec<u32>, Vec<[u8; 3]>) {
    let bits = cloud
        .xs()
        .iter()
        .chain(cloud.ys())
        .chain(cloud.zs())
        .map(|v| v.to_bits())
        .collect();
    (bits, cloud.colours().to_vec())
}
