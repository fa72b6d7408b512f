//! Many runs on a few threads: each worker takes the next job, runs it, and hands the result back
//! to the calling thread, which sees results as they finish.
//!
//! A batch's parallelism is its runs, one per worker, and each run stays on its worker's thread:
//! every worker is a one-thread rayon pool of its own, so the parallel loops inside a run (the
//! sensor's rows, the perception passes, ICP) run in order there instead of on the process-wide pool.
//! Sharing that pool made `--jobs N` put N runs' fine-grained tasks onto one set of threads: runs
//! waited on each other's tasks, and idle pool threads spun, so 16 jobs on 16 cores gave 3.8× one
//! job. Runs are independent, so one run per core wastes nothing but the batch's tail, which
//! starting the longest runs first keeps short ([`Schedule`]); and the results depend neither on the
//! number of threads (`world_determinism`) nor on the order runs start in.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::Instant;

use super::schedule::Schedule;
use crate::metrics::{RunMetrics, Start, measure};
use crate::run::runner;
use crate::scenario::Scenario;
use crate::score::{Scored, score};
use nudge_executive::record::Observer;
use nudge_executive::robot::Wrench;
use nudge_executive::{AbortReason, CandidatePolicy, Edge, RunReport, State};

/// One run to do.
pub struct Job<'a> {
    /// The scenario.
    pub scenario: &'a Scenario,
    /// Its file's name.
    pub file: &'a str,
    /// The run's seed.
    pub seed: u64,
    /// The candidate policy.
    pub policy: CandidatePolicy,
}

/// A finished run, scored against ground truth.
pub struct Done {
    /// The executive's report.
    pub report: RunReport,
    /// Each verdict against the truth.
    pub scored: Vec<Scored>,
    /// The largest wrist force seen during the run (N).
    pub peak_force: f64,
    /// The largest wrist force of the run's push tests and clearing pushes as a share of the force
    /// limit in force (1 = at the limit); `None` when the hand never pushed.
    pub force_share: Option<f64>,
    /// Wall-clock seconds the run took.
    pub wall: f64,
    /// The standard metrics (SPL, effort, INS, mistakes) against ground truth.
    pub metrics: RunMetrics,
}

/// Cancels every run in progress and keeps new ones from starting (Ctrl-C).
#[derive(Clone, Default)]
pub struct Cancel {
    stopped: Arc<AtomicBool>,
    running: Arc<Mutex<Vec<Arc<AtomicBool>>>>,
}

impl Cancel {
    /// Stops everything.
    pub fn stop(&self) {
        self.stopped.store(true, Ordering::Relaxed);
        if let Ok(flags) = self.running.lock() {
            for f in flags.iter() {
                f.store(true, Ordering::Relaxed);
            }
        }
    }

    /// True once [`Cancel::stop`] was called.
    pub fn is_stopped(&self) -> bool {
        self.stopped.load(Ordering::Relaxed)
    }

    fn watch(&self, flag: Arc<AtomicBool>) {
        if let Ok(mut flags) = self.running.lock() {
            flags.push(flag);
        }
        if self.is_stopped() {
            self.stop();
        }
    }
}

/// Remembers the largest wrist force of a run, and the largest as a share of the limit in force
/// while the hand pushes: a push test's limit in a push test, a clearing stroke's while clearing.
struct PeakForce {
    peak: f64,
    share: Option<f64>,
    /// The limit of the push under way (N), or `None` between pushes.
    limit: Option<f64>,
    test_limit: f64,
    clear_limit: f64,
}

impl PeakForce {
    fn new(force: &nudge_robot_model::ForceModel) -> Self {
        Self {
            peak: 0.0,
            share: None,
            limit: None,
            test_limit: force.test_limit,
            clear_limit: force.clear_limit,
        }
    }
}

impl Observer for PeakForce {
    fn transition(&mut self, _stamp: f64, _from: Option<&State>, _edge: Edge, to: &State) {
        self.limit = match to {
            State::PushTest { .. } => Some(self.test_limit),
            State::ClearPath { .. } => Some(self.clear_limit),
            _ => None,
        };
    }

    fn wrench(&mut self, _stamp: f64, wrench: &Wrench) {
        let f = wrench.force_norm();
        self.peak = self.peak.max(f);
        if let Some(limit) = self.limit {
            self.share = Some(self.share.unwrap_or(0.0).max(f / limit));
        }
    }
}

/// Why a job has no result.
#[derive(Debug, thiserror::Error)]
pub enum NotDone {
    /// Ctrl-C stopped it before its end: it says nothing about the scenario.
    #[error("cancelled")]
    Cancelled,
    /// Its world could not be built.
    #[error(transparent)]
    Failed(#[from] crate::world::WorldError),
}

/// Runs one job to its end and scores it.
pub fn execute(job: &Job<'_>, cancel: &Cancel) -> Result<Done, NotDone> {
    let started = Instant::now();
    let config = crate::run::run_config(job.scenario, job.seed, job.policy);
    let mut runner = runner(
        job.scenario,
        job.seed,
        job.policy,
        PeakForce::new(&config.model.force),
    )?;
    let start = Start::of(job.scenario, runner.robot().world());
    cancel.watch(runner.cancel_flag());
    let report = runner.run();
    if matches!(report.outcome, State::Aborted(AbortReason::Cancelled, _)) {
        return Err(NotDone::Cancelled);
    }
    let wall = started.elapsed().as_secs_f64();
    let (robot, peak) = runner.into_parts();
    let scored = score(&report, &robot);
    let metrics = measure(&start, &report, robot.world(), &scored);
    Ok(Done {
        report,
        scored,
        peak_force: peak.peak,
        force_share: peak.share,
        wall,
        metrics,
    })
}

/// Runs `jobs` on `threads` worker threads; `on_done(index, result)` is called on this thread as
/// each finishes, in completion order. Jobs start longest first as far as the runs so far tell
/// ([`Schedule`]); jobs not started when `cancel` stops are skipped.
pub fn run_all(
    jobs: &[Job<'_>],
    threads: usize,
    cancel: &Cancel,
    mut on_done: impl FnMut(usize, Result<Done, NotDone>),
) {
    // A kind is one scenario under one policy: the same room and task, other seeds.
    let kind_of: Vec<usize> = jobs
        .iter()
        .map(|job| {
            jobs.iter()
                .position(|other| {
                    std::ptr::eq(other.scenario, job.scenario) && other.policy == job.policy
                })
                .unwrap_or(0)
        })
        .collect();
    let schedule = &Mutex::new(Schedule::new(&kind_of));
    let (sender, receiver) = mpsc::channel();
    std::thread::scope(|scope| {
        for _ in 0..threads.clamp(1, jobs.len().max(1)) {
            let sender = sender.clone();
            scope.spawn(move || {
                let Ok(pool) = one_thread_pool() else {
                    // No pool: the runs use the shared one, slower when many run, same results.
                    return work(jobs, schedule, cancel, &sender);
                };
                pool.install(|| work(jobs, schedule, cancel, &sender));
            });
        }
        drop(sender);
        for (i, result) in receiver {
            on_done(i, result);
        }
    });
}

/// A rayon pool whose only thread is the caller's own, so `install` runs on it without a hand-off.
pub(super) fn one_thread_pool() -> Result<rayon::ThreadPool, rayon::ThreadPoolBuildError> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .use_current_thread()
        .build()
}

/// One worker's loop: takes the next job until none is left or the batch is cancelled.
fn work(
    jobs: &[Job<'_>],
    schedule: &Mutex<Schedule>,
    cancel: &Cancel,
    sender: &mpsc::Sender<(usize, Result<Done, NotDone>)>,
) {
    // A poisoned lock means another worker panicked mid-update; the schedule stays usable.
    let lock = || {
        schedule
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    };
    loop {
        if cancel.is_stopped() {
            break;
        }
        let started = Instant::now();
        let Some(i) = lock().start(started) else {
            break;
        };
        let Some(job) = jobs.get(i) else {
            break;
        };
        let result = execute(job, cancel);
        lock().finish(i, started.elapsed());
        if sender.send((i, result)).is_err() {
            break;
        }
    }
}
