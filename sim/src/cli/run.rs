//! `nudge run`: one scenario, its timeline, its summary.

use std::fs::File;
use std::process::ExitCode;
use std::sync::atomic::Ordering;
use std::time::Instant;

use crate::run::{run_config, taped_runner};
use anyhow::Context;
use nudge_executive::record::{McapRecorder, RunInfo, RunSummary, view_cloud_stride};
use nudge_executive::{CandidatePolicy, RunReport, State};

use super::map::{MapCollector, draw};
use super::source::Source;
use super::timeline::{TimelinePrinter, verdict_word};
use super::{EXIT_ABORTED, EXIT_NO_PATH, RobotKind, RunArgs};

pub(super) fn run(args: RunArgs) -> anyhow::Result<ExitCode> {
    let Source {
        file: file_name,
        text,
        scenario,
    } = match &args.scenario {
        Some(path) => Source::load(path)?,
        None => Source::default_room()?,
    };
    let seed = args.seed.unwrap_or(scenario.seed);
    let policy: CandidatePolicy = args.policy.map(Into::into).unwrap_or_default();
    if args.robot == RobotKind::Ros2 {
        return run_ros2(&args, &scenario, &file_name, seed, policy);
    }
    let mut recorder = match &args.record {
        Some(path) => {
            let info = RunInfo {
                scenario: scenario.name.clone(),
                seed,
                version: env!("CARGO_PKG_VERSION").to_string(),
                policy: format!("{policy:?}").to_lowercase(),
                scenario_file: Some((file_name.clone(), text)),
            };
            let mut recorder = McapRecorder::create(path, &info)?;
            let cell = run_config(&scenario, seed, policy).grid.resolution;
            let stride = args.record_cloud_stride.map_or_else(
                || view_cloud_stride(&scenario.robot.model().camera, cell),
                |n| n as usize,
            );
            recorder.set_cloud_stride(stride);
            Some(recorder)
        }
        None => None,
    };
    println!(
        "nudge: {} ({file_name}), seed {seed}, policy {policy:?}",
        scenario.name
    );
    let printer = TimelinePrinter {
        enabled: !args.quiet,
    };
    let map_file = match &args.map {
        Some(path) => {
            Some(File::create(path).with_context(|| format!("cannot create {}", path.display()))?)
        }
        None => None,
    };
    let map = map_file.as_ref().map(|_| MapCollector::new(&scenario));
    // A recording carries the replay tape: every adapter call and its result (`nudge replay`).
    let camera = scenario.robot.model().camera;
    let tape = recorder.as_mut().map(|r| r.start_tape(&camera));
    let mut runner = taped_runner(&scenario, seed, policy, (printer, (recorder, map)), tape)?;
    let cancel = runner.cancel_flag();
    // Ctrl-C cancels the run safely (the arm retracts, the recording is finished); a second one is
    // the operating system's.
    let _ = ctrlc::set_handler(move || cancel.store(true, Ordering::Relaxed));
    let started = Instant::now();
    let report = runner.run();
    let wall = started.elapsed().as_secs_f64();
    let (robot, (_, (recorder, map))) = runner.into_parts();
    let robot = robot.into_inner();
    // Contacts with people, from the simulation's truth, where the scenario has people.
    let people = (!robot.world().actors().is_empty()).then(|| {
        let effort = robot.world().effort();
        (effort.people_contacts, effort.pushed_into_people)
    });
    // Obstacles kept where the truth has nothing, with their ids and where they stand.
    let ghosts: Vec<String> = {
        let truth = crate::truth::Truth::new(robot.world());
        report
            .obstacles
            .iter()
            .filter(|p| crate::metrics::ghosts::is_ghost(p, &truth))
            .map(|p| {
                let at = crate::score::centroid(p);
                format!("{} at ({:.2}, {:.2})", p.id, at.x, at.y)
            })
            .collect()
    };
    if let (Some(mut recorder), Some(path)) = (recorder, &args.record) {
        recorder.write_summary(report.robot_time, &RunSummary::of(&report));
        match recorder.finish() {
            Ok(_) => println!("recording: {}", path.display()),
            Err(e) => eprintln!("nudge: recording {} is incomplete: {e}", path.display()),
        }
    }
    if let (Some(map), Some(file), Some(path)) = (map, map_file, &args.map) {
        match draw(&map, file, path) {
            Ok(()) => println!(
                "map: {} ({} push-test force panels below the map)",
                path.display(),
                map.tests.len()
            ),
            Err(e) => eprintln!("nudge: {e:#}"),
        }
    }
    summarise(&report, wall);
    if let Some((robot, pushed)) = people {
        println!(
            "people       {robot} contact(s) with the robot's body or hand, {pushed} with an object it pushed"
        );
    }
    if ghosts.is_empty() {
        println!("ghosts       none: every obstacle kept stands on something real");
    } else {
        println!(
            "ghosts       {} obstacle(s) kept where nothing is: {}",
            ghosts.len(),
            ghosts.join(", ")
        );
    }
    Ok(match report.outcome {
        State::Goal => ExitCode::SUCCESS,
        State::NoPathToGoal(_) => ExitCode::from(EXIT_NO_PATH),
        _ => ExitCode::from(EXIT_ABORTED),
    })
}

/// A run over ROS 2: the executive drives whatever robot answers on the configured topics. Ground
/// truth (ghosts, people) is the robot's to know, so the summary has none; a recording holds the
/// run's timeline without the replay tape.
fn run_ros2(
    args: &RunArgs,
    scenario: &crate::scenario::Scenario,
    file_name: &str,
    seed: u64,
    policy: CandidatePolicy,
) -> anyhow::Result<ExitCode> {
    if args.record.is_some() || args.map.is_some() {
        anyhow::bail!("--record and --map need the simulated robot's truth: not with --robot ros2");
    }
    let config = super::sim_bridge::ros2_config(args.ros2.as_deref())?;
    println!(
        "nudge: {} ({file_name}), seed {seed}, policy {policy:?}, robot over ROS 2 (domain {}, {} time)",
        scenario.name,
        config.domain_id,
        if config.use_sim_time {
            "simulated"
        } else {
            "wall"
        }
    );
    let robot =
        nudge_ros2::adapter::Ros2Robot::connect(config, scenario.robot.model(), "nudge_executive")
            .context("cannot reach the robot over ROS 2")?;
    let printer = TimelinePrinter {
        enabled: !args.quiet,
    };
    let mut runner = nudge_executive::Runner::new(
        robot,
        printer,
        crate::run::run_config(scenario, seed, policy),
    );
    let cancel = runner.cancel_flag();
    let _ = ctrlc::set_handler(move || cancel.store(true, Ordering::Relaxed));
    let started = Instant::now();
    let report = runner.run();
    let wall = started.elapsed().as_secs_f64();
    summarise(&report, wall);
    Ok(match report.outcome {
        State::Goal => ExitCode::SUCCESS,
        State::NoPathToGoal(_) => ExitCode::from(EXIT_NO_PATH),
        _ => ExitCode::from(EXIT_ABORTED),
    })
}

fn summarise(report: &RunReport, wall: f64) {
    println!();
    let outcome = match &report.outcome {
        State::Goal => "reached the goal".to_string(),
        State::NoPathToGoal(e) => format!(
            "no path to the goal ({})",
            e.no_path.as_deref().unwrap_or("no reason")
        ),
        State::Aborted(reason, _) => format!("aborted: {reason}"),
        other => format!("ended in {}", other.name()),
    };
    println!("outcome      {outcome}");
    let explanation = &report.knowledge.explanation;
    println!("push tests   {}", report.knowledge.push_tests);
    for t in &explanation.tests {
        println!("  {t}");
    }
    for (id, verdict) in &explanation.verdicts {
        println!("verdict      {id} is {}", verdict_word(verdict));
    }
    for (id, why) in &explanation.unpushable {
        println!("unpushable   {id}: {why}");
    }
    for (id, why) in &explanation.set_aside {
        println!("set aside    {id}: {why}");
    }
    for (id, n) in &explanation.jams {
        println!("jammed       {id}: {n} time(s) while clearing");
    }
    for (k, v) in explanation.views.iter().enumerate() {
        println!(
            "view {:<7} looked from ({:.2}, {:.2}) facing {:.0}° for {} ({:.2} m² predicted, {:.1} m walk)",
            k + 1,
            v.view.position.x,
            v.view.position.y,
            v.view.yaw.to_degrees(),
            v.question.name(),
            v.view.gain,
            v.view.walk
        );
    }
    if matches!(report.outcome, State::NoPathToGoal(_)) {
        for r in &explanation.unseen {
            println!("unseen       {r}");
        }
        for r in &report.sequences {
            println!("sequence     {r}");
        }
    }
    println!("robot time   {:.1} s", report.robot_time);
    println!("wall time    {wall:.2} s");
    if wall > 0.0 {
        println!("real-time    {:.0}×", report.robot_time / wall);
    }
}
