//! The pure transition function: (state, knowledge, event, config) → (next state, knowledge, commands).
//!
//! No I/O, no clock, no robot: the runner executes the commands and feeds back events, so every edge
//! of the loop can be unit-tested with plain values. Every transition names its [`Edge`], which is how
//! the tests prove they cover the whole machine.

use std::collections::{BTreeMap, BTreeSet};

use nudge_perception::ObjectId;

use crate::command::Command;
use crate::config::ExecutiveConfig;
use crate::event::{Candidate, Event, SetAside, SetAsideWhy};
use crate::explain::{Explanation, TestRecord};
use crate::push_test::{Ambiguity, Finding, PushEvidence, PushIntent, Verdict, classify};
use crate::state::{AbortReason, Approach, Purpose, State};
use crate::view::{Question, UnseenRegion, ViewRecord};

/// What the executive has learnt so far in a run.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Knowledge {
    /// Tests, verdicts, unpushable objects, jams and the last no-path reason.
    pub explanation: Explanation,
    /// Push tests started (retests included).
    pub push_tests: u32,
    /// Replans (blocked walks and invalidated paths).
    pub replans: u32,
    /// Clearing pushes finished per object.
    pub clears: BTreeMap<ObjectId, u32>,
    /// Looks taken while waiting for an object that may move by itself, per object.
    pub waits: BTreeMap<ObjectId, u32>,
    /// Looks taken because a push test's hand met nothing where the object was seen, per object.
    pub misses: BTreeMap<ObjectId, u32>,
    /// Objects that gave way to a push test's hand where colour ICP could not measure them: they
    /// were looked at again before being tested again, once each.
    pub moved_unmeasured: BTreeSet<ObjectId>,
    /// Viewpoints asked for because a push of the object needed floor not yet seen, per object.
    pub looks_for: BTreeMap<ObjectId, u32>,
    /// Objects whose push may stand on or sweep over floor nobody has seen: no viewpoint could show
    /// it, and the guarded stroke still stops at whatever is there.
    pub unseen_ok: BTreeSet<ObjectId>,
    /// Walks to a stand pose that were blocked, per object: after `max_jams` of them the object is
    /// settled, as one that jammed is, so a walk blocked again and again does not loop until the
    /// replan limit.
    pub approach_blocks: BTreeMap<ObjectId, u32>,
    /// Objects whose push was put off because something that may be a person stood near it or its
    /// sweep: with nothing else left, the robot waits for them as for a mover in the way.
    pub person_near: BTreeSet<ObjectId>,
}

/// Every edge of the machine, for timelines and coverage.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Edge {
    /// (no state) → LookAround: the run's first step, which leaves no state. Timelines and observers
    /// get `None` for the state left; printed and recorded as `(start) -> LookAround (Start)`.
    Start,
    /// LookAround → DetectObjects.
    LookAroundDone,
    /// DetectObjects → PlanPath.
    Detected,
    /// PlanPath → Navigate.
    PathFound,
    /// PlanPath → SelectCandidate.
    NoPath,
    /// Navigate → Goal.
    ReachedGoal,
    /// Navigate → LookAround: the grid flagged the path or a new obstacle lies on it; the walk stops and
    /// the robot looks again, so the new obstacle becomes an obstacle the planner and the push test know.
    PathInvalidated,
    /// Navigate → LookAround: the robot reported its walk blocked.
    WalkBlocked,
    /// A replan past the limit → Stopping.
    ReplanLimit,
    /// SelectCandidate → ApproachPushPose(Clear): the candidate is already known movable.
    KnownMovable,
    /// SelectCandidate → LookAround: the candidate moved lately or is movable on passive evidence only
    /// (it was seen moving and came to rest), as a person who stopped is; or nothing is left to push but
    /// something in the way moved lately. Look again, so something that moves by itself has time to go.
    WaitForMover,
    /// SelectCandidate → ApproachPushPose(Test).
    Candidate,
    /// A push test past the limit → Stopping.
    PushTestLimit,
    /// SelectCandidate → PlanView(Way): nothing is left to push; look for floor not yet seen that
    /// could open a way before giving up.
    LookForWay,
    /// ApproachPushPose(Planning) → ApproachPushPose(Walking).
    PushPlanned,
    /// ApproachPushPose(Planning) → SelectCandidate: no push, and no unseen floor could change that.
    NoPushPlan,
    /// ApproachPushPose(Planning) → SelectCandidate: a push was planned, but something that may be a
    /// person stands near the object or its sweep; the next candidate comes first, and with none left
    /// the robot waits for them (within the run's waits for movers).
    PersonNearPush,
    /// ApproachPushPose(Planning) → PlanView(Push): no push, but floor around or under the object is
    /// unseen; look before ruling it out.
    LookForPush,
    /// ApproachPushPose(Planning) or PlanView(Push) → ApproachPushPose(Planning): the views for this
    /// object are spent, or no viewpoint shows its floor: plan the push allowing unseen floor (the
    /// guarded stroke stops at whatever is there).
    PushIntoUnseen,
    /// Navigate → PlanView(PathAhead): the path runs over floor the walking camera cannot see in time
    /// (around a corner, past a jamb); the walk stops before it.
    UnseenAhead,
    /// PlanView(PathAhead) → Navigate: no viewpoint shows that floor; walk on over it, watching.
    WalkIntoUnseen,
    /// PlanView → GoToView: the view planner chose where to look from.
    ViewPlanned,
    /// PlanView(Way) → NoPathToGoal: no reachable viewpoint shows floor that could open a way.
    NothingLeftToSee,
    /// Any question with the view budget spent: answered as if no viewpoint could help.
    ViewLimit,
    /// GoToView → LookAround: at the viewpoint, facing its heading.
    AtViewpoint,
    /// GoToView → LookAround: the walk to the viewpoint was blocked or its path flagged.
    ViewBlocked,
    /// ApproachPushPose(Walking, Test) → PushTest.
    AtPushPoseForTest,
    /// ApproachPushPose(Walking, Clear) → ClearPath.
    AtPushPoseForClear,
    /// ApproachPushPose(Walking) → LookAround: the approach walk was blocked.
    ApproachBlocked,
    /// ApproachPushPose(AfterTest) → ClearPath: no clearing push can be planned without a look (or
    /// at all): the test's push is finished, the paper's loop.
    FinishTestPush,
    /// PushTest → SelectCandidate: static.
    FoundStatic,
    /// PushTest → ClearPath: movable, the test's push opening the way; else → ApproachPushPose
    /// (AfterTest): the clearing push is planned afresh.
    FoundMovable,
    /// PushTest → PushTest: ambiguous, retest once.
    Retest,
    /// PushTest → LookAround: the hand swept where the object was seen and met nothing (the smear of
    /// something that moved during the look, or a misplaced obstacle): look again, once per object,
    /// rather than push at empty space.
    NothingThere,
    /// PushTest → LookAround: the object gave way to the hand (its stroke under the force limit)
    /// but colour ICP could not measure it: it moved, and may have turned, so a retest along the
    /// same line would meet it where it no longer stands. Look again, once per object, and test it
    /// where it now is.
    MovedUnmeasured,
    /// PushTest → SelectCandidate: ambiguous twice, taken as static.
    AmbiguousTwice,
    /// PushTest → ClearPath (as [`Edge::FoundMovable`]): ambiguous twice, but in both tests the hand
    /// pushed on after contact with the force under the limit: the object gave way, whatever ICP
    /// could not confirm (a static object stops the hand within the wrist's compliance, a millimetre
    /// or two).
    YieldedTwice,
    /// PushTest → ClearPath (as [`Edge::FoundMovable`]): the retest found the object held at the
    /// limit, but the test before saw it slide with the hand for centimetres before it jammed. It
    /// moved, and what stopped it that way (a doorway's jamb a turned crate slid into) holds it
    /// now: a static object does not slide at all.
    SlidThenHeld,
    /// PushTest → SelectCandidate: the hand met nothing where the object was seen, again after a
    /// second look: a push there tests empty space, so the object gets no verdict (static would be a
    /// guess: nothing resisted) and is set aside as one no push reaches.
    MissedTwice,
    /// ClearPath → LookAround: the object moved as planned.
    Cleared,
    /// ClearPath → LookAround: the object turned or slid off the push line so far that the rest of
    /// its sweep would run into something; look, and plan the rest of the way from where it is.
    OffLine,
    /// ClearPath → LookAround: the object jammed at the force limit.
    Jammed,
    /// Stopping → Aborted.
    Stopped,
    /// Stopping → Aborted: the safe stop itself failed.
    StopFailed,
    /// Stopping absorbs everything but its own end.
    AlreadyStopping,
    /// Any running state → Stopping: cancelled.
    Cancel,
    /// Any running state → Stopping: an adapter call failed.
    RobotFailure,
    /// Any running state → Stopping: perception failed.
    PerceptionFailure,
    /// Any running state → Stopping: robot-time budget spent.
    TimeUp,
    /// An event the state does not expect → Stopping (a runner bug, never a panic).
    Unexpected,
    /// A terminal state ignores further events.
    AfterEnd,
}

impl Edge {
    /// Every edge, in declaration order.
    pub const ALL: [Edge; 51] = [
        Edge::Start,
        Edge::LookAroundDone,
        Edge::Detected,
        Edge::PathFound,
        Edge::NoPath,
        Edge::ReachedGoal,
        Edge::PathInvalidated,
        Edge::WalkBlocked,
        Edge::ReplanLimit,
        Edge::KnownMovable,
        Edge::WaitForMover,
        Edge::Candidate,
        Edge::PushTestLimit,
        Edge::LookForWay,
        Edge::PushPlanned,
        Edge::NoPushPlan,
        Edge::PersonNearPush,
        Edge::LookForPush,
        Edge::PushIntoUnseen,
        Edge::UnseenAhead,
        Edge::WalkIntoUnseen,
        Edge::ViewPlanned,
        Edge::NothingLeftToSee,
        Edge::ViewLimit,
        Edge::AtViewpoint,
        Edge::ViewBlocked,
        Edge::AtPushPoseForTest,
        Edge::AtPushPoseForClear,
        Edge::ApproachBlocked,
        Edge::FinishTestPush,
        Edge::FoundStatic,
        Edge::FoundMovable,
        Edge::Retest,
        Edge::NothingThere,
        Edge::MovedUnmeasured,
        Edge::AmbiguousTwice,
        Edge::YieldedTwice,
        Edge::SlidThenHeld,
        Edge::MissedTwice,
        Edge::Cleared,
        Edge::OffLine,
        Edge::Jammed,
        Edge::Stopped,
        Edge::StopFailed,
        Edge::AlreadyStopping,
        Edge::Cancel,
        Edge::RobotFailure,
        Edge::PerceptionFailure,
        Edge::TimeUp,
        Edge::Unexpected,
        Edge::AfterEnd,
    ];
}

/// The result of one transition.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    /// The next state.
    pub state: State,
    /// What the executive knows after the transition.
    pub knowledge: Knowledge,
    /// What the runner must do next, in order.
    pub commands: Vec<Command>,
    /// Which edge fired.
    pub edge: Edge,
}

/// The first step of a run: look around.
pub fn start() -> Step {
    Step {
        state: State::LookAround,
        knowledge: Knowledge::default(),
        commands: vec![Command::LookAround],
        edge: Edge::Start,
    }
}

/// The transition function.
pub fn transition(
    state: &State,
    knowledge: &Knowledge,
    event: &Event,
    config: &ExecutiveConfig,
) -> Step {
    let mut k = knowledge.clone();
    if state.is_terminal() {
        return step(state.clone(), k, vec![], Edge::AfterEnd);
    }
    if let State::Stopping(reason) = state {
        return match event {
            Event::Stopped => aborted(reason.clone(), k, Edge::Stopped),
            Event::RobotFailed(_) => aborted(reason.clone(), k, Edge::StopFailed),
            _ => step(state.clone(), k, vec![], Edge::AlreadyStopping),
        };
    }
    match event {
        Event::Cancel => return stopping(AbortReason::Cancelled, k, Edge::Cancel),
        Event::RobotFailed(e) => {
            return stopping(AbortReason::Robot(e.clone()), k, Edge::RobotFailure);
        }
        Event::PerceptionFailed(e) => {
            return stopping(
                AbortReason::Perception(e.clone()),
                k,
                Edge::PerceptionFailure,
            );
        }
        Event::TimeUp(t) => return stopping(AbortReason::TimeLimit(*t), k, Edge::TimeUp),
        _ => {}
    }

    match (state, event) {
        (State::LookAround, Event::LookedAround { .. }) => step(
            State::DetectObjects,
            k,
            vec![Command::DetectObjects],
            Edge::LookAroundDone,
        ),
        (State::DetectObjects, Event::ObjectsDetected { gone, .. }) => {
            // What stood in the way of a push ruled out may be what went (a person beyond a
            // chair): pushes ruled out are asked about afresh.
            if *gone > 0 {
                k.explanation.unpushable.clear();
            }
            step(State::PlanPath, k, vec![Command::PlanPath], Edge::Detected)
        }
        (State::PlanPath, Event::PathFound { .. }) => step(
            State::Navigate,
            k,
            vec![Command::FollowPath {
                stop_at_unseen: true,
            }],
            Edge::PathFound,
        ),
        (State::PlanPath, Event::NoPath { reason }) => {
            k.explanation.no_path = Some(reason.clone());
            select_candidate(k, config, Edge::NoPath)
        }
        (State::Navigate, Event::Arrived) => step(State::Goal, k, vec![], Edge::ReachedGoal),
        (State::Navigate, Event::PathInvalidated { .. }) => replan(
            k,
            config,
            State::LookAround,
            vec![Command::StopWalk, Command::WatchAhead, Command::LookAround],
            Edge::PathInvalidated,
        ),
        (State::Navigate, Event::WalkBlocked) => replan(
            k,
            config,
            State::LookAround,
            vec![Command::LookAround],
            Edge::WalkBlocked,
        ),
        (State::Navigate, Event::UnseenAhead { .. }) => plan_view(
            Question::PathAhead,
            k,
            config,
            vec![Command::StopWalk],
            Edge::UnseenAhead,
        ),
        (State::PlanView { question }, Event::ViewPlanned(view)) => {
            k.explanation.views.push(ViewRecord {
                question: question.clone(),
                view: view.clone(),
            });
            step(
                State::GoToView {
                    question: question.clone(),
                    view: view.clone(),
                },
                k,
                vec![Command::WalkToView(view.clone())],
                Edge::ViewPlanned,
            )
        }
        (State::PlanView { question }, Event::NoView { unseen, .. }) => {
            no_view(question, unseen.clone(), k, vec![], false)
        }
        (State::GoToView { .. }, Event::Arrived) => {
            // Seen from a new place, the obstacles are perceived afresh: a push ruled out from where
            // the robot stood before (an object seen in parts, its floor unseen) may be possible now.
            k.explanation.unpushable.clear();
            step(
                State::LookAround,
                k,
                vec![Command::LookAround],
                Edge::AtViewpoint,
            )
        }
        (State::GoToView { .. }, Event::WalkBlocked) => replan(
            k,
            config,
            State::LookAround,
            vec![Command::LookAround],
            Edge::ViewBlocked,
        ),
        (State::GoToView { .. }, Event::PathInvalidated { .. }) => replan(
            k,
            config,
            State::LookAround,
            vec![Command::StopWalk, Command::WatchAhead, Command::LookAround],
            Edge::ViewBlocked,
        ),
        (State::SelectCandidate, Event::CandidatesRanked { ranked, set_aside }) => {
            k.explanation.set_aside = set_aside
                .iter()
                .map(|s| (s.id, why_set_aside(s, &k)))
                .collect();
            pick(ranked, k, config)
        }
        (
            State::ApproachPushPose {
                target,
                purpose,
                phase: Approach::Planning | Approach::AfterTest(_),
            },
            Event::PushPlanned(intent),
        ) if intent.target == *target => step(
            State::ApproachPushPose {
                target: *target,
                purpose: *purpose,
                phase: Approach::Walking(intent.clone()),
            },
            k,
            vec![Command::WalkToPushPose(intent.clone())],
            Edge::PushPlanned,
        ),
        (
            State::ApproachPushPose {
                target,
                phase: Approach::AfterTest(test),
                ..
            },
            Event::NoPushPlan { .. },
        ) => step(
            State::ClearPath {
                target: *target,
                intent: test.clone(),
            },
            k,
            vec![Command::ClearPath(test.clone())],
            Edge::FinishTestPush,
        ),
        (
            State::ApproachPushPose {
                target,
                purpose,
                phase: Approach::Planning,
            },
            Event::NoPushPlan { reason, unseen },
        ) => {
            if *unseen && !k.unseen_ok.contains(target) {
                return look_for_push(*target, *purpose, k, config);
            }
            k.explanation.unpushable.insert(*target, reason.clone());
            select_candidate(k, config, Edge::NoPushPlan)
        }
        (
            State::ApproachPushPose {
                target,
                phase: Approach::Planning,
                ..
            },
            Event::PersonNearPush { reason },
        ) => {
            k.explanation.unpushable.insert(*target, reason.clone());
            k.person_near.insert(*target);
            select_candidate(k, config, Edge::PersonNearPush)
        }
        (
            State::ApproachPushPose {
                target,
                purpose,
                phase: Approach::Walking(intent),
            },
            Event::Arrived,
        ) => match purpose {
            Purpose::Test => {
                start_push_test(*target, intent, 1, k, config, Edge::AtPushPoseForTest)
            }
            Purpose::Clear => step(
                State::ClearPath {
                    target: *target,
                    intent: intent.clone(),
                },
                k,
                vec![Command::ClearPath(intent.clone())],
                Edge::AtPushPoseForClear,
            ),
        },
        (
            State::ApproachPushPose {
                target,
                phase: Approach::Walking(_),
                ..
            },
            Event::WalkBlocked,
        ) => {
            *k.approach_blocks.entry(*target).or_default() += 1;
            replan(
                k,
                config,
                State::LookAround,
                vec![Command::LookAround],
                Edge::ApproachBlocked,
            )
        }
        (
            State::PushTest {
                target,
                intent,
                attempt,
            },
            Event::PushTestDone(evidence),
        ) => conclude_push_test(*target, intent, *attempt, evidence, k, config),
        (State::ClearPath { target, .. }, Event::Cleared { moved }) => {
            *k.clears.entry(*target).or_default() += 1;
            // A clearing push that moved the object proves it movable as a push test would: one
            // cleared on the grid's passive evidence alone (something moved and came to rest
            // there) gets the verdict its push earned.
            if *moved >= config.classifier.agreement_abs {
                k.explanation
                    .verdicts
                    .entry(*target)
                    .or_insert(Verdict::Movable);
            }
            // What was pushed may have stood in the way of pushes ruled out before (a box beside
            // it, whose stand pose it filled): those are asked about afresh after the look.
            k.explanation.unpushable.clear();
            step(
                State::LookAround,
                k,
                vec![Command::LookAround],
                Edge::Cleared,
            )
        }
        (State::ClearPath { target, .. }, Event::OffLine { .. }) => {
            // Counted as a clear: an object that goes off line push after push is given up like one
            // cleared too often. It moved: pushes ruled out before are asked about afresh.
            *k.clears.entry(*target).or_default() += 1;
            k.explanation.unpushable.clear();
            step(
                State::LookAround,
                k,
                vec![Command::LookAround],
                Edge::OffLine,
            )
        }
        (State::ClearPath { target, .. }, Event::Jammed { .. }) => {
            *k.explanation.jams.entry(*target).or_default() += 1;
            step(
                State::LookAround,
                k,
                vec![Command::LookAround],
                Edge::Jammed,
            )
        }
        (state, event) => stopping(
            AbortReason::Internal(format!(
                "event {} is not expected in state {}",
                event.name(),
                state.name()
            )),
            k,
            Edge::Unexpected,
        ),
    }
}

fn step(state: State, knowledge: Knowledge, commands: Vec<Command>, edge: Edge) -> Step {
    Step {
        state,
        knowledge,
        commands,
        edge,
    }
}

fn stopping(reason: AbortReason, k: Knowledge, edge: Edge) -> Step {
    step(State::Stopping(reason), k, vec![Command::SafeStop], edge)
}

fn aborted(reason: AbortReason, k: Knowledge, edge: Edge) -> Step {
    let explanation = k.explanation.clone();
    step(State::Aborted(reason, explanation), k, vec![], edge)
}

/// Counts a replan, or stops when the budget is spent.
fn replan(
    mut k: Knowledge,
    config: &ExecutiveConfig,
    next: State,
    commands: Vec<Command>,
    edge: Edge,
) -> Step {
    if k.replans >= config.max_replans {
        return stopping(
            AbortReason::ReplanLimit(config.max_replans),
            k,
            Edge::ReplanLimit,
        );
    }
    k.replans += 1;
    step(next, k, commands, edge)
}

/// Objects that need no further push: decided static, impossible to push, jammed, cleared or their
/// approach blocked too often.
fn settled(k: &Knowledge, config: &ExecutiveConfig) -> Vec<ObjectId> {
    let e = &k.explanation;
    let mut out: Vec<ObjectId> = e.static_objects();
    out.extend(e.unpushable.keys().copied());
    out.extend(
        e.jams
            .iter()
            .filter(|(_, n)| **n >= config.max_jams)
            .map(|(id, _)| *id),
    );
    out.extend(
        k.clears
            .iter()
            .filter(|(_, n)| **n >= config.max_clears_per_object)
            .map(|(id, _)| *id),
    );
    out.extend(
        k.approach_blocks
            .iter()
            .filter(|(_, n)| **n >= config.max_jams)
            .map(|(id, _)| *id),
    );
    out.sort();
    out.dedup();
    out
}

/// Looks around again, counting a wait on `id`. What blocked a push before may have walked away
/// meanwhile (a person standing in its sweep), so pushes ruled out are asked about afresh.
fn wait_for(id: ObjectId, mut k: Knowledge) -> Step {
    *k.waits.entry(id).or_insert(0) += 1;
    k.explanation.unpushable.clear();
    k.person_near.clear();
    step(
        State::LookAround,
        k,
        vec![Command::LookAround],
        Edge::WaitForMover,
    )
}

fn select_candidate(k: Knowledge, config: &ExecutiveConfig, edge: Edge) -> Step {
    let exclude = settled(&k, config);
    step(
        State::SelectCandidate,
        k,
        vec![Command::RankCandidates {
            policy: config.policy,
            exclude,
        }],
        edge,
    )
}

/// Why an obstacle was set aside, for the explanation: its size, or that it was taken for room
/// structure, and for one a push test found movable, that its outline now takes in what it was
/// pushed against.
fn why_set_aside(s: &SetAside, k: &Knowledge) -> String {
    let movable = k
        .explanation
        .verdicts
        .get(&s.id)
        .is_some_and(Verdict::is_movable);
    let why = match s.why {
        SetAsideWhy::TooLarge { extent, limit } => {
            format!("{extent:.2} m across, more than the {limit:.1} m the robot pushes")
        }
        SetAsideWhy::Structure => {
            "taken for room structure: at the edge of all that was seen, its top out of view".into()
        }
    };
    if movable {
        format!("{why}: found movable, its outline now takes in what it was pushed against")
    } else {
        why
    }
}

fn pick(list: &[Candidate], k: Knowledge, config: &ExecutiveConfig) -> Step {
    let exclude = settled(&k, config);
    let waited = |k: &Knowledge, id: ObjectId| k.waits.get(&id).copied().unwrap_or(0);
    let tested_movable = |id: ObjectId| {
        k.explanation
            .verdicts
            .get(&id)
            .is_some_and(Verdict::is_movable)
    };
    // Something seen moving where it stands that passive evidence does not call movable may be a
    // person who stopped: it is never push-tested. Anything else in the way comes first; with only
    // such movers (or excluded obstacles that moved lately) left, the robot looks again while the
    // run's waits for movers last: each look may see the way clear.
    let mover = |c: &Candidate| c.seen_moving && !c.passively_movable && !tested_movable(c.id);
    let Some(candidate) = list.iter().find(|c| !exclude.contains(&c.id) && !mover(c)) else {
        let waits: u32 = k.waits.values().sum();
        if let Some(m) = list
            .iter()
            .find(|c| mover(c))
            .filter(|_| waits < config.mover_waits)
        {
            return wait_for(m.id, k);
        }
        // A push put off for a person near it: they may have left by the next look.
        if let Some(&id) = k
            .person_near
            .iter()
            .next()
            .filter(|_| waits < config.mover_waits)
        {
            return wait_for(id, k);
        }
        // Nothing left to push, but something in the way moved lately: it may walk on. The run's
        // waits bound these too: each look may find what moved as a new obstacle (ids are never
        // reused), and a per-obstacle count alone looked again until the run's time ran out.
        if let Some(m) = list
            .iter()
            .find(|c| c.moved_lately && waited(&k, c.id) < config.passive_waits)
            .filter(|_| waits < config.mover_waits)
        {
            return wait_for(m.id, k);
        }
        return plan_view(Question::Way, k, config, vec![], Edge::LookForWay);
    };
    let tested_movable = tested_movable(candidate.id);
    // Something that may move by itself (seen moving lately, or movable on passive evidence alone,
    // as a person who stopped is) is looked at again before it is pushed.
    // The run's waits bound these as well: what moved may be found anew, under a new id, by each
    // look.
    let may_walk_on = candidate.moved_lately || candidate.passively_movable;
    let waits: u32 = k.waits.values().sum();
    if may_walk_on
        && !tested_movable
        && waited(&k, candidate.id) < config.passive_waits
        && waits < config.mover_waits
    {
        return wait_for(candidate.id, k);
    }
    // A clearing push that moved the object as planned proved it movable, as a push test would; the
    // grid's passive evidence is gone by then (the robot's own push wrote its cells).
    let cleared_before = k.clears.get(&candidate.id).is_some_and(|n| *n > 0);
    let known_movable = candidate.passively_movable || tested_movable || cleared_before;
    let (purpose, edge) = if known_movable {
        (Purpose::Clear, Edge::KnownMovable)
    } else {
        if k.push_tests >= config.max_push_tests {
            return stopping(
                AbortReason::PushTestLimit(config.max_push_tests),
                k,
                Edge::PushTestLimit,
            );
        }
        (Purpose::Test, Edge::Candidate)
    };
    let allow_unseen = k.unseen_ok.contains(&candidate.id);
    step(
        State::ApproachPushPose {
            target: candidate.id,
            purpose,
            phase: Approach::Planning,
        },
        k,
        vec![Command::PlanPush {
            target: candidate.id,
            purpose,
            allow_unseen,
        }],
        edge,
    )
}

/// Asks the view planner where to look from to answer `question`, after `first` (stopping a walk);
/// with the view budget spent, answers as if no viewpoint could help.
fn plan_view(
    question: Question,
    k: Knowledge,
    config: &ExecutiveConfig,
    first: Vec<Command>,
    edge: Edge,
) -> Step {
    if k.explanation.views.len() >= config.max_views as usize {
        return no_view(&question, Vec::new(), k, first, true);
    }
    let mut commands = first;
    commands.push(Command::PlanView(question.clone()));
    step(State::PlanView { question }, k, commands, edge)
}

/// What follows when no viewpoint would show the floor that matters (or the view budget is spent):
/// a way → no path, with the unseen regions; a push → planned over the unseen floor; the path ahead
/// → walked over it.
fn no_view(
    question: &Question,
    unseen: Vec<UnseenRegion>,
    mut k: Knowledge,
    first: Vec<Command>,
    budget_spent: bool,
) -> Step {
    let named = |edge: Edge| if budget_spent { Edge::ViewLimit } else { edge };
    let mut commands = first;
    match question {
        Question::Way => {
            k.explanation.unseen = unseen;
            let explanation = k.explanation.clone();
            step(
                State::NoPathToGoal(explanation),
                k,
                commands,
                named(Edge::NothingLeftToSee),
            )
        }
        Question::Push { target, purpose } => {
            k.unseen_ok.insert(*target);
            commands.push(Command::PlanPush {
                target: *target,
                purpose: *purpose,
                allow_unseen: true,
            });
            step(
                State::ApproachPushPose {
                    target: *target,
                    purpose: *purpose,
                    phase: Approach::Planning,
                },
                k,
                commands,
                named(Edge::PushIntoUnseen),
            )
        }
        Question::PathAhead => {
            commands.push(Command::FollowPath {
                stop_at_unseen: false,
            });
            step(State::Navigate, k, commands, named(Edge::WalkIntoUnseen))
        }
    }
}

/// A push of `target` needs floor not yet seen: look for it, as often as `views_per_push` allows;
/// then plan it over the unseen floor.
fn look_for_push(
    target: ObjectId,
    purpose: Purpose,
    mut k: Knowledge,
    config: &ExecutiveConfig,
) -> Step {
    let looked = k.looks_for.get(&target).copied().unwrap_or(0);
    if looked >= config.views_per_push {
        k.unseen_ok.insert(target);
        return step(
            State::ApproachPushPose {
                target,
                purpose,
                phase: Approach::Planning,
            },
            k,
            vec![Command::PlanPush {
                target,
                purpose,
                allow_unseen: true,
            }],
            Edge::PushIntoUnseen,
        );
    }
    k.looks_for.insert(target, looked + 1);
    plan_view(
        Question::Push { target, purpose },
        k,
        config,
        vec![],
        Edge::LookForPush,
    )
}

fn start_push_test(
    target: ObjectId,
    intent: &PushIntent,
    attempt: u8,
    mut k: Knowledge,
    config: &ExecutiveConfig,
    edge: Edge,
) -> Step {
    if k.push_tests >= config.max_push_tests {
        return stopping(
            AbortReason::PushTestLimit(config.max_push_tests),
            k,
            Edge::PushTestLimit,
        );
    }
    k.push_tests += 1;
    step(
        State::PushTest {
            target,
            intent: intent.clone(),
            attempt,
        },
        k,
        vec![Command::PushTest {
            intent: intent.clone(),
            attempt,
        }],
        edge,
    )
}

/// Whether the last two tests of `target` (the retest just recorded and the test before it) both
/// saw the object give way under the hand: pushed on for centimetres under the limit
/// ([`crate::push_test::ClassifierConfig::gave_way`]), or slid with it before it jammed
/// ([`crate::push_test::ClassifierConfig::slid_with_hand`]).
fn gave_way_twice(tests: &[TestRecord], target: ObjectId, config: &ExecutiveConfig) -> bool {
    let mut last = tests.iter().rev().filter(|t| t.object == target).take(2);
    let classifier = &config.classifier;
    let gave = |t: &TestRecord| {
        let hand = t.hand_travel_mm / 1e3;
        classifier.gave_way(t.reached_limit, hand)
            || matches!(t.finding, Finding::Ambiguous(Ambiguity::MovedThenLimit { icp })
                if classifier.slid_with_hand(icp, hand))
    };
    matches!((last.next(), last.next()), (Some(a), Some(b)) if gave(a) && gave(b))
}

/// Whether the test of `target` before the one just recorded saw it slide with the hand before it
/// jammed ([`crate::push_test::ClassifierConfig::slid_with_hand`]).
fn slid_before(tests: &[TestRecord], target: ObjectId, config: &ExecutiveConfig) -> bool {
    let before = tests.iter().rev().filter(|t| t.object == target).nth(1);
    before.is_some_and(|t| {
        matches!(t.finding, Finding::Ambiguous(Ambiguity::MovedThenLimit { icp })
            if config.classifier.slid_with_hand(icp, t.hand_travel_mm / 1e3))
    })
}

fn conclude_push_test(
    target: ObjectId,
    intent: &PushIntent,
    attempt: u8,
    evidence: &PushEvidence,
    mut k: Knowledge,
    config: &ExecutiveConfig,
) -> Step {
    let finding = classify(evidence, &config.classifier);
    k.explanation.tests.push(TestRecord {
        object: target,
        attempt,
        peak_force: evidence.peak_force,
        icp_mm: evidence.icp.map(|icp| icp.displacement * 1e3),
        hand_travel_mm: evidence.hand_travel * 1e3,
        reached_limit: evidence.reached_limit,
        stop_lean_deg: evidence.stop_lean.map(f64::to_degrees),
        finding: finding.clone(),
    });
    let push_test = k.push_tests;
    let verdict_step = |mut k: Knowledge, verdict: Verdict, edge: Edge| {
        k.explanation.verdicts.insert(target, verdict.clone());
        let mark = Command::MarkVerdict {
            target,
            verdict: verdict.clone(),
            push_test,
        };
        if verdict.is_movable() && !intent.opens_way {
            // The test's push only had to move the object: plan the clearing push afresh, and
            // finish the test's push where that cannot be done without a look.
            let allow_unseen = k.unseen_ok.contains(&target);
            step(
                State::ApproachPushPose {
                    target,
                    purpose: Purpose::Clear,
                    phase: Approach::AfterTest(intent.clone()),
                },
                k,
                vec![
                    mark,
                    Command::PlanPush {
                        target,
                        purpose: Purpose::Clear,
                        allow_unseen,
                    },
                ],
                edge,
            )
        } else if verdict.is_movable() {
            step(
                State::ClearPath {
                    target,
                    intent: intent.clone(),
                },
                k,
                vec![mark, Command::ClearPath(intent.clone())],
                edge,
            )
        } else {
            let mut s = select_candidate(k, config, edge);
            s.commands.insert(0, mark);
            s
        }
    };
    match finding {
        Finding::Static if attempt >= 2 && slid_before(&k.explanation.tests, target, config) => {
            verdict_step(k, Verdict::Movable, Edge::SlidThenHeld)
        }
        Finding::Static => verdict_step(
            k,
            Verdict::Static {
                after_ambiguity: false,
            },
            Edge::FoundStatic,
        ),
        Finding::Movable => verdict_step(k, Verdict::Movable, Edge::FoundMovable),
        Finding::Ambiguous(Ambiguity::NoContact)
            if attempt < 2 && k.misses.get(&target).copied().unwrap_or(0) == 0 =>
        {
            k.misses.insert(target, 1);
            step(
                State::LookAround,
                k,
                vec![Command::LookAround],
                Edge::NothingThere,
            )
        }
        // A retest along the first test's line meets an object that slid and turned where it no
        // longer stands: a chair turned 27° was met edge-on, leaning 66°, and two ambiguous tests
        // read static.
        Finding::Ambiguous(Ambiguity::IcpFailed)
            if attempt < 2
                && config
                    .classifier
                    .gave_way(evidence.reached_limit, evidence.hand_travel)
                && !k.moved_unmeasured.contains(&target) =>
        {
            k.moved_unmeasured.insert(target);
            step(
                State::LookAround,
                k,
                vec![Command::LookAround],
                Edge::MovedUnmeasured,
            )
        }
        Finding::Ambiguous(Ambiguity::NoContact)
            if k.misses.get(&target).is_some_and(|n| *n > 0) =>
        {
            k.explanation.unpushable.insert(
                target,
                "the hand met nothing where it was seen, after a second look".into(),
            );
            select_candidate(k, config, Edge::MissedTwice)
        }
        // An object that tipped under the hand is retested at half the height: the push's moment
        // about the far edge halves, so it slides where it can before it tips (a uniform box does once
        // μ·h < d/2). The runner keeps the hand within the arm's reach.
        Finding::Ambiguous(Ambiguity::Tipped { .. }) if attempt < 2 => {
            let lower = PushIntent {
                hand_height: intent.hand_height / 2.0,
                clear_height: intent.hand_height / 2.0,
                ..intent.clone()
            };
            start_push_test(target, &lower, attempt + 1, k, config, Edge::Retest)
        }
        Finding::Ambiguous(_) if attempt < 2 => {
            start_push_test(target, intent, attempt + 1, k, config, Edge::Retest)
        }
        Finding::Ambiguous(_) if gave_way_twice(&k.explanation.tests, target, config) => {
            verdict_step(k, Verdict::Movable, Edge::YieldedTwice)
        }
        Finding::Ambiguous(_) => verdict_step(
            k,
            Verdict::Static {
                after_ambiguity: true,
            },
            Edge::AmbiguousTwice,
        ),
    }
}
