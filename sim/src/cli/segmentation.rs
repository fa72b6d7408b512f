//! `nudge segmentation`: perception's obstacles scored against the simulation's truth, one
//! look-around from each scenario's start (`crate::metrics::segmentation`).

use std::collections::BTreeMap;
use std::process::ExitCode;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use anyhow::Context;
use nudge_perception::detect_from_views;

use super::SegmentationArgs;
use super::source::{Source, expand};
use crate::adapter::SimRobot;
use crate::metrics::segmentation::{MIN_RETURNS, ObjectScore, labelled_look, score_look};

/// One look's scores, or why it could not be taken.
type Looked = anyhow::Result<Vec<ObjectScore>>;

/// A seen object's score, with the file and seed of the look that saw it.
type Seen = (String, u64, ObjectScore);

/// Per family: how many looks were taken, and every object they saw.
#[derive(Default)]
struct FamilyLooks {
    looks: usize,
    objects: Vec<Seen>,
}

pub(super) fn segmentation(args: SegmentationArgs) -> anyhow::Result<ExitCode> {
    let files = expand(&args.scenarios)?;
    let sources: Vec<Source> = files
        .iter()
        .map(|f| Source::load(f))
        .collect::<anyhow::Result<_>>()?;
    let jobs: Vec<(&Source, u64)> = sources
        .iter()
        .flat_map(|s| (0..args.seeds).map(move |k| (s, s.scenario.seed.wrapping_add(k))))
        .collect();
    let threads = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let results: Vec<Mutex<Option<Looked>>> = jobs.iter().map(|_| Mutex::new(None)).collect();
    let next = AtomicUsize::new(0);
    std::thread::scope(|scope| {
        for _ in 0..threads.min(jobs.len()) {
            scope.spawn(|| {
                // One look per thread at a time, its rays on this thread alone (as `nudge batch`).
                let pool = super::pool::one_thread_pool();
                loop {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    let Some((source, seed)) = jobs.get(k) else {
                        break;
                    };
                    let looked = match &pool {
                        Ok(pool) => pool.install(|| look(source, *seed)),
                        Err(e) => Err(anyhow::anyhow!("no thread pool: {e}")),
                    };
                    if let Ok(mut slot) = results[k].lock() {
                        *slot = Some(looked);
                    }
                }
            });
        }
    });
    // Per family: the looks, and every seen object's score.
    let mut families: BTreeMap<String, FamilyLooks> = BTreeMap::new();
    for ((source, seed), slot) in jobs.iter().zip(results) {
        let looked = slot
            .into_inner()
            .ok()
            .flatten()
            .unwrap_or_else(|| Err(anyhow::anyhow!("the look was not taken")));
        let scores = looked.with_context(|| format!("{} seed {seed}", source.file))?;
        let family = source
            .scenario
            .family
            .clone()
            .unwrap_or_else(|| source.scenario.name.clone());
        let entry = families.entry(family).or_default();
        entry.looks += 1;
        entry
            .objects
            .extend(scores.into_iter().map(|o| (source.file.clone(), *seed, o)));
    }
    println!(
        "one look-around from each start; objects seen with at least {MIN_RETURNS} returns above the floor band"
    );
    println!(
        "{:<24} {:>5}  {:>7} {:>7} {:>7} {:>7}  {:>7} {:>7} {:>7}",
        "family", "looks", "objects", "purity", "compl.", "both ok", "struct.", "purity", "compl."
    );
    let mut all: Vec<Seen> = Vec::new();
    for (family, FamilyLooks { looks, objects }) in &families {
        let (pushable, long): (Vec<_>, Vec<_>) = objects.iter().partition(|(_, _, o)| o.pushable);
        let (p, c, ok) = means(&pushable);
        let (lp, lc, _) = means(&long);
        println!(
            "{family:<24} {looks:>5}  {:>7} {p:>7.3} {c:>7.3} {ok:>7.3}  {:>7} {lp:>7.3} {lc:>7.3}",
            pushable.len(),
            long.len()
        );
        all.extend(objects.iter().cloned());
    }
    println!(
        "purity, compl.: means over the things to push (lower than the room's walls, no longer than \
         the robot's largest candidate); both ok: share with purity >= 0.97 and completeness >= 0.95; \
         struct.: the room's structure (partitions as tall as the walls, longer things)"
    );
    if args.objects {
        all.sort_by(|a, b| {
            let worst = |o: &ObjectScore| o.purity.min(o.completeness);
            worst(&a.2).total_cmp(&worst(&b.2))
        });
        println!(
            "\n{:<28} {:>5} {:<16} {:>7} {:>7} {:>7}",
            "file", "seed", "object", "returns", "purity", "compl."
        );
        for (file, seed, o) in &all {
            println!(
                "{file:<28} {seed:>5} {:<16} {:>7} {:>7.3} {:>7.3}",
                o.name, o.returns, o.purity, o.completeness
            );
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// One labelled look-around from the start of `source`'s scenario, detected and scored.
fn look(source: &Source, seed: u64) -> Looked {
    let scenario = &source.scenario;
    let mut robot = SimRobot::new(scenario, seed)?;
    let goal = nalgebra::Point2::new(scenario.goal.position[0], scenario.goal.position[1]);
    let run = nudge_executive::RunConfig::new(
        scenario.robot.model(),
        goal,
        scenario.goal.tolerance,
        seed,
    );
    // Perception as the executive runs it for this robot.
    let config = &run.perception;
    let look = labelled_look(&mut robot, config)?;
    let prisms = detect_from_views(&look.views, &look.base, config, &[])?.prisms;
    Ok(score_look(
        &look,
        &prisms,
        scenario,
        config.segment.low_height,
        run.max_candidate_extent,
    ))
}

/// Mean purity, mean completeness, and the share of objects meeting both bars.
fn means(objects: &[&Seen]) -> (f64, f64, f64) {
    if objects.is_empty() {
        return (f64::NAN, f64::NAN, f64::NAN);
    }
    let n = objects.len() as f64;
    let purity = objects.iter().map(|(_, _, o)| o.purity).sum::<f64>() / n;
    let completeness = objects.iter().map(|(_, _, o)| o.completeness).sum::<f64>() / n;
    let ok = objects
        .iter()
        .filter(|(_, _, o)| o.purity >= 0.97 && o.completeness >= 0.95)
        .count() as f64
        / n;
    (purity, completeness, ok)
}
