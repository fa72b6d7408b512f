//! The runner: drives any [`Robot`] through the machine, tick by tick.
//!
//! The machine decides ([`crate::machine::transition`]); the runner executes its commands — robot
//! actions, perception, planning — and feeds back exactly one event per step. Robot actions are started
//! and polled every [`RunConfig::tick`] of robot time, so the runner can watch sensors, honour a cancel
//! request and the robot-time budget while anything runs. Nothing here reads the wall clock.

mod clear;
mod config;
mod floor_index;
mod fragments;
mod grid;
mod look;
mod movers;
mod navigate;
mod object;
mod outline;
mod push;
mod rank;
mod recheck;
mod report;
mod search_space;
mod split;
mod stroke;
mod unseen;
mod view;
mod watchdog;
mod world;

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

pub use config::{GridSetup, PushMotionConfig, RunConfig, ViewSetup};
pub use report::{Decision, RunReport, TimelineEntry};
use watchdog::Watchdog;
use world::WorldModel;

use crate::command::Command;
use crate::event::Event;
use crate::machine::{Knowledge, Step, start, transition};
use crate::record::{LogLevel, Observer, RobotFrames};
use crate::robot::{ActionStatus, Robot, RobotError};
use crate::state::State;

/// Why a wait for an action ended early.
#[derive(Debug)]
pub(crate) enum Interrupt {
    /// Cancelled from outside.
    Cancel,
    /// The robot-time budget is spent (robot time, s).
    TimeUp(f64),
    /// An adapter call failed.
    Robot(RobotError),
}

impl From<RobotError> for Interrupt {
    fn from(e: RobotError) -> Self {
        Interrupt::Robot(e)
    }
}

impl From<Interrupt> for Event {
    fn from(i: Interrupt) -> Self {
        match i {
            Interrupt::Cancel => Event::Cancel,
            Interrupt::TimeUp(t) => Event::TimeUp(t),
            Interrupt::Robot(e) => Event::RobotFailed(e.to_string()),
        }
    }
}

/// Drives a robot through one run.
///
/// Every action it starts has a deadline derived from the action (see `watchdog.rs`): an adapter
/// whose action never reports done ends the run in a safe stop and `Aborted`, not in a wait for the
/// whole robot-time budget.
pub struct Runner<R: Robot, O: Observer> {
    robot: Watchdog<R>,
    observer: O,
    config: RunConfig,
    world: WorldModel,
    rng: ChaCha8Rng,
    cancel: Arc<AtomicBool>,
    start_time: f64,
    /// Robot time let pass when the run started (s), counted by the watchdog.
    start_elapsed: f64,
}

impl<R: Robot, O: Observer> Runner<R, O> {
    /// A runner for `robot`, reporting to `observer`.
    pub fn new(robot: R, observer: O, config: RunConfig) -> Self {
        let rng = ChaCha8Rng::seed_from_u64(config.seed);
        Self {
            robot: Watchdog::new(robot, &config.model),
            observer,
            config,
            world: WorldModel::default(),
            rng,
            cancel: Arc::new(AtomicBool::new(false)),
            start_time: 0.0,
            start_elapsed: 0.0,
        }
    }

    /// A flag that, once set (from another thread or a signal handler), cancels the run safely.
    pub fn cancel_flag(&self) -> Arc<AtomicBool> {
        Arc::clone(&self.cancel)
    }

    /// The robot, e.g. to read ground truth from a simulation after the run.
    pub fn robot(&self) -> &R {
        self.robot.inner()
    }

    /// The observer, e.g. to finish a recording.
    pub fn into_parts(self) -> (R, O) {
        (self.robot.into_inner(), self.observer)
    }

    /// Runs until the machine reaches a terminal state and reports the outcome.
    pub fn run(&mut self) -> RunReport {
        self.start_time = self.robot.now();
        self.start_elapsed = self.robot.elapsed();
        self.start_grid();
        let mut timeline = Vec::new();
        let mut decisions = std::collections::BTreeMap::new();
        let mut tests_begun = std::collections::BTreeMap::new();
        let mut step = start();
        self.record(&mut timeline, None, &step);
        while !step.state.is_terminal() {
            let Some(event) = self.execute(&step.commands) else {
                break;
            };
            let next = transition(&step.state, &step.knowledge, &event, &self.config.executive);
            self.record(&mut timeline, Some(&step.state), &next);
            self.note_test_begun(&step.state, &next.state, &mut tests_begun);
            self.report_verdicts(
                &step.knowledge,
                &next.knowledge,
                &event,
                &tests_begun,
                &mut decisions,
            );
            step = next;
        }
        RunReport {
            outcome: step.state,
            knowledge: step.knowledge,
            robot_time: self.robot.now() - self.start_time,
            timeline,
            obstacles: self.world.prisms.clone(),
            joined: self.world.objects.joins(),
            sequences: self.world.sequences.clone(),
            grid: self.world.grid.clone(),
            decisions,
        }
    }

    fn record(&mut self, timeline: &mut Vec<TimelineEntry>, from: Option<&State>, step: &Step) {
        let stamp = self.robot.now();
        self.observer
            .transition(stamp, from, step.edge, &step.state);
        timeline.push(TimelineEntry {
            stamp,
            from: from.map(State::name),
            edge: step.edge,
            to: step.state.name(),
        });
    }

    /// Notes the obstacle and the time when a first push test of it begins (`to` a push test of
    /// attempt 1 entered from another state): the object as it stood before the test's own strokes
    /// moved it.
    fn note_test_begun(
        &self,
        from: &State,
        to: &State,
        begun: &mut std::collections::BTreeMap<nudge_perception::ObjectId, Decision>,
    ) {
        if let State::PushTest {
            target, attempt: 1, ..
        } = to
            && !matches!(from, State::PushTest { target: t, .. } if t == target)
            && let Some(prism) = self.world.prisms.iter().find(|p| p.id == *target)
        {
            let stamp = self.robot.now();
            begun.insert(
                *target,
                Decision {
                    stamp,
                    prism: prism.clone(),
                },
            );
        }
    }

    /// Tells the observer of each verdict a push test just reached, and notes in `decisions` what
    /// the verdict is about: the obstacle and the time when its first test began (`begun`).
    fn report_verdicts(
        &mut self,
        before: &Knowledge,
        after: &Knowledge,
        event: &Event,
        begun: &std::collections::BTreeMap<nudge_perception::ObjectId, Decision>,
        decisions: &mut std::collections::BTreeMap<nudge_perception::ObjectId, Decision>,
    ) {
        let Event::PushTestDone(evidence) = event else {
            return;
        };
        let stamp = self.robot.now();
        for (id, verdict) in &after.explanation.verdicts {
            if before.explanation.verdicts.get(id) != Some(verdict) {
                self.observer.verdict(stamp, *id, verdict, evidence);
                match begun.get(id) {
                    Some(decision) => {
                        decisions.insert(*id, decision.clone());
                    }
                    None => {
                        decisions.remove(id);
                    }
                }
            }
        }
    }

    /// Executes a step's commands in order; the last one that reports an event ends the step, or
    /// the first that fails (an adapter error, a cancel, the time budget): the commands after it
    /// would start work on a robot that did not do what came before (a walk that failed to stop),
    /// and their event would hide the failure from the machine.
    fn execute(&mut self, commands: &[Command]) -> Option<Event> {
        let mut event = None;
        for command in commands {
            if let Some(e) = self.execute_one(command) {
                let failed = matches!(e, Event::RobotFailed(_) | Event::Cancel | Event::TimeUp(_));
                event = Some(e);
                if failed {
                    break;
                }
            }
        }
        if event.is_none() && !commands.is_empty() {
            let stamp = self.robot.now();
            self.observer.note(
                stamp,
                LogLevel::Error,
                "a step's commands reported no event",
            );
        }
        event
    }

    fn execute_one(&mut self, command: &Command) -> Option<Event> {
        if self.cancel.load(Ordering::Relaxed) && !matches!(command, Command::SafeStop) {
            return Some(Event::Cancel);
        }
        match command {
            Command::LookAround => Some(self.look_around()),
            Command::DetectObjects => Some(self.detect_objects()),
            Command::PlanPath => Some(self.plan_path()),
            Command::FollowPath { stop_at_unseen } => Some(self.follow_path(*stop_at_unseen)),
            Command::StopWalk => self
                .robot
                .stop_walk()
                .err()
                .map(|e| Interrupt::Robot(e).into()),
            Command::WatchAhead => self.watch_ahead().err().map(Into::into),
            Command::RankCandidates { policy, exclude } => Some(self.rank(*policy, exclude)),
            Command::PlanPush {
                target,
                purpose,
                allow_unseen,
            } => Some(self.plan_push(*target, *purpose, *allow_unseen)),
            Command::PlanView(question) => Some(self.plan_view(question)),
            Command::WalkToView(view) => Some(self.walk_to_view(view)),
            Command::WalkToPushPose(intent) => Some(self.walk_to_push_pose(intent)),
            Command::PushTest { intent, .. } => Some(self.push_test(intent)),
            Command::MarkVerdict {
                target,
                verdict,
                push_test,
            } => {
                let stamp = self.robot.now();
                self.observer.note(
                    stamp,
                    LogLevel::Info,
                    &format!("{target} marked {verdict:?}"),
                );
                self.mark_verdict(*target, verdict, *push_test);
                None
            }
            Command::ClearPath(intent) => Some(self.clear_path(intent)),
            Command::SafeStop => Some(self.safe_stop()),
        }
    }

    /// Lets one tick of robot time pass, honouring cancel and the time budget, and reports frames.
    pub(crate) fn tick(&mut self) -> Result<(), Interrupt> {
        if self.cancel.load(Ordering::Relaxed) {
            return Err(Interrupt::Cancel);
        }
        // The budget counts the robot time let pass, not the clock's reading: a clock that steps (an
        // NTP correction) neither ends the run at once nor lets it run an hour over.
        let elapsed = self.robot.elapsed() - self.start_elapsed;
        if elapsed >= self.config.executive.max_robot_time {
            return Err(Interrupt::TimeUp(elapsed));
        }
        self.robot.advance(self.config.tick)?;
        self.report_frames()?;
        Ok(())
    }

    fn report_frames(&mut self) -> Result<(), RobotError> {
        let base = self.robot.base_pose()?;
        // The floor under the robot is seen floor: it stands there.
        if let Some(grid) = &self.world.grid {
            let at = nalgebra::Point2::from(base.value.translation.vector);
            self.world
                .memory
                .tread(grid.geometry(), at, self.config.model.body.radius);
        }
        let head = self.robot.head_angles()?.value;
        let hand = self.robot.hand_position()?.value;
        let camera = look::camera_pose(&base.value, head, self.config.model.head.height);
        self.observer.frames(
            base.stamp,
            &RobotFrames {
                base: base.value,
                head,
                camera,
                hand,
            },
        );
        Ok(())
    }

    /// Polls `status` every tick until the action is done.
    pub(crate) fn wait<T>(
        &mut self,
        mut status: impl FnMut(&mut Watchdog<R>) -> Result<ActionStatus<T>, RobotError>,
    ) -> Result<T, Interrupt> {
        loop {
            if let ActionStatus::Done(outcome) = status(&mut self.robot)? {
                return Ok(outcome);
            }
            self.tick()?;
        }
    }

    /// Retracts the arm and stops the base, ignoring the cancel flag (this is how a cancel ends).
    fn safe_stop(&mut self) -> Event {
        let result = (|| -> Result<(), RobotError> {
            self.robot.stop_walk()?;
            self.robot.stop_hand()?;
            self.robot.start_retract()?;
            // The watchdog's deadline for a retract, counted here in ticks: the watchdog itself
            // is what may have stopped the run.
            let bound = watchdog::retract_deadline(&self.config.model.arm);
            let ticks = (bound / self.config.tick.max(1e-6)).ceil() as u64;
            for _ in 0..ticks {
                if let ActionStatus::Done(_) = self.robot.hand_status()? {
                    return Ok(());
                }
                self.robot.advance(self.config.tick)?;
            }
            Err(RobotError::Timeout {
                capability: "arm",
                seconds: ticks as f64 * self.config.tick,
            })
        })();
        match result {
            Ok(()) => Event::Stopped,
            Err(e) => Event::RobotFailed(e.to_string()),
        }
    }
}
