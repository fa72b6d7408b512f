//! Everything a run needs to know besides the robot.

use nalgebra::Point2;
use nudge_motion::planner::rrt_connect::RrtConnect;
use nudge_motion::{
    BlockingConfig, Budget, LookCoverage, PushConfig, RobotCylinder, SequenceConfig, Shortcut,
    ValidityConfig,
};
use nudge_perception::PerceptionConfig;
use nudge_perception::grid::{ColumnReduction, DEFAULT_RESOLUTION, GridConfig};

use nudge_robot_model::RobotModel;

use crate::config::ExecutiveConfig;

/// How the hand pushes during a push test and a clearing push.
#[derive(Clone, Debug, PartialEq)]
pub struct PushMotionConfig {
    /// Hand speed along the push (m/s). Slow, as a guarded move must be: the impact at first contact
    /// grows with speed and must stay well under the force limit.
    pub speed: f64,
    /// Hand speed (m/s) of a guarded approach to a stroke's start where the look does not show the
    /// way there clear. A guarded move's force rises by the wrist's stiffness × speed per control
    /// period once it touches, and its damping adds damping × speed at the touch: at 5 cm/s, with
    /// the paper's 1 kHz loop and a wrist of 20 kN/m damped at 200 N·s/m, 1 N per period on top of
    /// 10 N, so the guard stops it within the 10 % the force limit allows. Faster than the push (a
    /// long way round at 2 cm/s would cost many seconds); far slower than the free 0.2 m/s, at which
    /// a touch reads 40 N at once.
    pub approach_speed: f64,
    /// The hand starts this far before the expected contact (m).
    pub approach_gap: f64,
    /// A push test pushes this far past the expected contact (m).
    pub test_travel: f64,
    /// Guard of a stroke's touch (N): the hand moves at its leg's speed until it reads this, stops,
    /// and presses on from there (see [`Self::press_acceleration`]). A touch reads the wrist's
    /// damping × speed at once and its stiffness × speed per control period on top of the guard,
    /// about 4.5 N at 2 cm/s with the paper's wrist (20 kN/m, 200 N·s/m, 1 kHz): 5 N keeps a touch
    /// under 10 N, half the 20 N limit, the least margin any object can need (the midpoint between
    /// a weightless object's sliding force and the limit), and 25 times the wrist's noise above zero.
    pub touch_force: f64,
    /// Largest acceleration of the hand while it presses on from a touch (m/s²). Against an object
    /// that holds, the force rises at the wrist's stiffness × the hand's speed, so the hand reaches
    /// the object's sliding force F at the speed √(2·a·ΔF/k) and the object starts from rest with
    /// the hand moving at that speed: an excess of at most speed × √(k·m) over F (a mass on a
    /// spring; damping only lowers it). Pressing ΔF = 15 N more (5 N to the 20 N limit) at 0.01 m/s²
    /// breaks a 20 kg object (the heaviest the limit slides on floors with μ ≥ 0.1) free at 3.9
    /// mm/s, an excess under 2.4 N at worst — the least margin a scored object has is 2 N ((20 N −
    /// 16 N) / 2), and the wrist's damping takes about half off — and once it slides, its
    /// acceleration to the push speed costs m·a = 0.2 N. The push speed is reached 2 cm in.
    pub press_acceleration: f64,
    /// Points this far around an object's footprint belong to it when cropping for ICP (m).
    pub crop_margin: f64,
}

impl Default for PushMotionConfig {
    fn default() -> Self {
        Self {
            speed: 0.02,
            approach_speed: 0.05,
            approach_gap: 0.08,
            test_travel: 0.15,
            touch_force: 5.0,
            press_acceleration: 0.01,
            crop_margin: 0.06,
        }
    }
}

/// The obstacle-type grid the run keeps, and how it watches the path while walking.
#[derive(Clone, Debug, PartialEq)]
pub struct GridSetup {
    /// Cell side (m). Default 50 mm.
    pub resolution: f64,
    /// Corners of the area the grid covers (map frame, m), e.g. the room. `None`: the box around the
    /// start and the goal grown by [`Self::margin`] on every side.
    pub area: Option<(Point2<f64>, Point2<f64>)>,
    /// Growth of the start–goal box when no area is given (m). Default 4 m: a few rooms' worth.
    pub margin: f64,
    /// The passive rules' tuning.
    pub rules: GridConfig,
    /// How a colour range frame is reduced to beams (heights above the floor that block).
    pub reduction: ColumnReduction,
    /// Robot time between frames taken while walking a path (s). Default 1 s: a person at walking
    /// speed moves 1–1.5 m in that time, within the camera's view ahead.
    pub watch_period: f64,
    /// How long the robot stands and watches ahead after the grid flagged its path, before it looks
    /// around (s). Default 3 s: a person leaving something on the way and walking on is seen doing it,
    /// and what is left rests in view for Tamura's three frames and more.
    pub settle_time: f64,
    /// Robot time between frames while it watches (s). Default 0.1 s, near the camera's frame rate:
    /// a person walking at 1 m/s moves less than the moving rule's step (0.15 m) between two frames,
    /// so the grid follows them and sees what they leave behind come to rest.
    pub settle_period: f64,
    /// Head tilt while walking (rad, down positive). Default 20°: the floor is in view from about
    /// 1.8 m out to the range limit, so anything stepping onto the path ahead is seen.
    pub watch_tilt: f64,
    /// Share of an obstacle's footprint cells that must be passively Movable for it to count as known
    /// movable without a push test. Default 0.3.
    pub passive_share: f64,
    /// Frames from a camera tilted further down than this (rad) stay out of the grid. A frame proves
    /// a cell free only at the heights its rays pass through there; one whose upper edge dips far
    /// below the horizon sees the floor under a table top and then the top itself, which the passive
    /// rules would take for something appearing. Default 22°: the 20° frames go in (the
    /// look-around's shallowest row, the walking and watching frames); the look-around's 30° and 45°
    /// rows and the looks at an object around a push (42° to 50° in the paper's room) stay out. With
    /// the SR-4000's 34.6° vertical field a 20° frame's upper edge lies 2.7° below the horizon and a
    /// 22° frame's 4.7°; the 30° row's, 12.7°, would show a table top after the floor beneath it.
    pub max_tilt: f64,
    /// An obstacle counts as having moved lately when the grid saw one of its cells (or one next to
    /// them) Moving in a look or a walk within this many seconds (s). Default 30.
    pub mover_memory: f64,
}

impl Default for GridSetup {
    fn default() -> Self {
        Self {
            resolution: DEFAULT_RESOLUTION,
            area: None,
            margin: 4.0,
            rules: GridConfig::default(),
            reduction: ColumnReduction::default(),
            watch_period: 1.0,
            settle_time: 3.0,
            settle_period: 0.1,
            watch_tilt: 20f64.to_radians(),
            passive_share: 0.3,
            max_tilt: 22f64.to_radians(),
            mover_memory: 30.0,
        }
    }
}

/// Moving to see: how viewpoints are chosen (the camera and the walk are the robot's: see
/// [`RunConfig::model`]).
#[derive(Clone, Debug, PartialEq)]
pub struct ViewSetup {
    /// Gap between candidate viewpoints (m). Default 0.25 m: a stand pose a few grid cells off shows
    /// nearly the same floor, and the view planner's cost grows with the candidates' number.
    pub spacing: f64,
}

impl Default for ViewSetup {
    fn default() -> Self {
        Self { spacing: 0.25 }
    }
}

/// A run's parameters.
#[derive(Clone, Debug)]
pub struct RunConfig {
    /// Limits, policy and the push test's thresholds.
    pub executive: ExecutiveConfig,
    /// Perception's stages (the look-around's views included).
    pub perception: PerceptionConfig,
    /// What the robot is: its body, head, camera, arm, wrist and force limits. The run takes every
    /// robot fact from here; [`RunConfig::new`] also derives `push` and `validity` from it, so a
    /// model changed afterwards needs those set again.
    pub model: RobotModel,
    /// Which prisms block the cylinder.
    pub validity: ValidityConfig,
    /// The goal (map frame, m).
    pub goal: Point2<f64>,
    /// Radius of the goal region (m).
    pub goal_tolerance: f64,
    /// The path planner.
    pub planner: RrtConnect,
    /// Its budget per query.
    pub budget: Budget,
    /// Path shortcutting.
    pub shortcut: Shortcut,
    /// Push planning.
    pub push: PushConfig,
    /// The `blocking` policy's query.
    pub blocking: BlockingConfig,
    /// The search for two pushes that together open the way, when no single push does.
    pub sequence: SequenceConfig,
    /// How the hand pushes.
    pub push_motion: PushMotionConfig,
    /// The obstacle-type grid.
    pub grid: GridSetup,
    /// Moving to see.
    pub view: ViewSetup,
    /// Clearance kept between the robot's cylinder and every obstacle when planning (m): the walk stops
    /// a little short of contact, and perception's footprints are a few millimetres off.
    pub clearance: f64,
    /// A remembered obstacle out of view is forgotten once this many floor points are seen inside its
    /// footprint (it was moved away).
    pub forget_after_floor_points: usize,
    /// Prisms within this distance (m) of the edge of everything seen are room structure (walls).
    pub structure_margin: f64,
    /// Prisms wider than this (m) are walls or furniture too large to push, never candidates.
    pub max_candidate_extent: f64,
    /// Robot time between polls of a running action (s).
    pub tick: f64,
    /// Seed of every random choice in the run.
    pub seed: u64,
}

impl RunConfig {
    /// Height (m) of the highest point a look-around shows at horizontal distance `d` from the eye:
    /// where the top ray of its least tilted view passes (`eye − d · tan(min tilt − v_fov/2)`). A
    /// surface whose top lies below this was seen whole in height; a wall's top never is.
    pub fn top_in_view(&self, d: f64) -> f64 {
        let min_tilt = self
            .perception
            .look_around
            .tilts_deg
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min)
            .to_radians();
        self.model.head.height - d * (min_tilt - self.model.camera.v_fov() / 2.0).tan()
    }

    /// The robot's bounding cylinder, as the planners see it.
    pub fn cylinder(&self) -> RobotCylinder {
        RobotCylinder {
            radius: self.model.body.radius,
            height: self.model.body.height,
        }
    }

    /// Nearest floor in view with the head tilted `tilt` down (m): where the lower edge of the
    /// camera's field of view meets the floor.
    pub fn floor_near(&self, tilt: f64) -> f64 {
        let down = (tilt + self.model.camera.v_fov() / 2.0).min(std::f64::consts::FRAC_PI_2);
        self.model.head.height / down.tan().max(1e-9)
    }

    /// The floor a look-around shows from where the robot stands: the head's camera through the
    /// look-around's views ([`LookCoverage::from_camera`]); the paper's SR-4000 on HRP-2 when the
    /// camera or the views make no sense.
    pub fn look_coverage(&self) -> LookCoverage {
        LookCoverage::from_robot(&self.model, &self.perception.look_around)
    }

    /// Defaults for `model` heading to `goal`.
    pub fn new(model: RobotModel, goal: Point2<f64>, goal_tolerance: f64, seed: u64) -> Self {
        let mut perception = PerceptionConfig::default();
        // Colour tells touching things apart beyond what this camera's colour noise explains.
        if let Some(hue) = perception.elevation.hue.as_mut() {
            hue.noise = model.camera.colour_noise;
        }
        Self {
            executive: ExecutiveConfig::default(),
            // The push planner reads footprints made of perception's elevation cells, and pushes as
            // far as the camera sees.
            push: PushConfig {
                footprint_cell: perception.elevation.cell_size,
                ..PushConfig::for_robot(&model)
            },
            perception,
            validity: ValidityConfig::for_body(&model.body),
            goal,
            goal_tolerance,
            planner: RrtConnect::default(),
            budget: Budget::iterations(20_000),
            shortcut: Shortcut::default(),
            blocking: BlockingConfig::default(),
            sequence: SequenceConfig::default(),
            push_motion: PushMotionConfig::default(),
            grid: GridSetup {
                reduction: ColumnReduction {
                    max_height: model.body.height,
                    ..ColumnReduction::default()
                },
                ..GridSetup::default()
            },
            view: ViewSetup::default(),
            model,
            clearance: 0.08,
            forget_after_floor_points: 30,
            structure_margin: 0.15,
            max_candidate_extent: 2.0,
            tick: 0.05,
            seed,
        }
    }
}
