//! The fake robot's scripted objects: how one answers a push, and the contact a guarded move makes.

use nalgebra::Vector2;

/// How the scripted object in front of the hand answers a push.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ObjectResponse {
    /// A static object: force grows with penetration at this stiffness (N/m).
    Static {
        /// Contact stiffness (N/m).
        stiffness: f64,
    },
    /// A movable object sliding at a constant friction force (N) once touched.
    Sliding {
        /// Friction force while sliding (N).
        force: f64,
    },
    /// An object that slides at `force` until pushes have moved it `travel` metres in all, then
    /// holds like a static one of `stiffness` (it ran into something nobody scripted the camera to
    /// show).
    SlidesThenJams {
        /// Friction force while sliding (N).
        force: f64,
        /// How far it slides before it jams, over all pushes (m).
        travel: f64,
        /// Contact stiffness once jammed (N/m).
        stiffness: f64,
    },
}

impl ObjectResponse {
    /// A wall: static and stiff.
    pub const RIGID: ObjectResponse = ObjectResponse::Static {
        stiffness: 20_000.0,
    };

    /// How a push that has gone `depth` metres past first contact loads the hand (N), with the
    /// object able to give way `give` metres before it holds; the push's travel past `give` is
    /// against the object's stiffness.
    pub(super) fn force(&self, depth: f64, give: f64) -> f64 {
        let (sliding, stiffness) = match *self {
            ObjectResponse::Static { stiffness } => (0.0, stiffness),
            ObjectResponse::Sliding { force } => (force, 0.0),
            ObjectResponse::SlidesThenJams {
                force, stiffness, ..
            } => (force, stiffness),
        };
        if depth <= 0.0 {
            0.0
        } else if depth <= give {
            sliding
        } else {
            sliding + stiffness * (depth - give)
        }
    }

    /// How far the object gives way before it holds (m), having been pushed `moved` metres before.
    pub(super) fn give(&self, moved: f64) -> f64 {
        match *self {
            ObjectResponse::Static { .. } => 0.0,
            ObjectResponse::Sliding { .. } => f64::INFINITY,
            ObjectResponse::SlidesThenJams { travel, .. } => (travel - moved).max(0.0),
        }
    }
}

/// An object the next guarded moves touch after `contact_at` metres along their line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScriptedObject {
    /// Distance along the move's line where the hand first touches (m).
    pub contact_at: f64,
    /// How the object answers.
    pub response: ObjectResponse,
}

/// What the guarded move under way meets: where along its line, and how it answers.
#[derive(Clone, Copy, Debug)]
pub(super) struct Contact {
    /// Distance along the line of first contact (m).
    pub(super) at: f64,
    /// How the object answers.
    pub(super) response: ObjectResponse,
    /// How far it gives way before it holds (m).
    pub(super) give: f64,
    /// The scene box touched, if the contact comes from the scene.
    pub(super) target: Option<usize>,
    /// Push direction in the map frame, for moving the box.
    pub(super) direction: Vector2<f64>,
    /// How far this move has moved the box so far (m).
    pub(super) pushed: f64,
}
