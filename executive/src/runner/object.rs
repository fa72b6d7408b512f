//! What the run has learnt of each object, kept with the object under its id.
//!
//! Perception hands the runner obstacles afresh at every look ([`Prism`]s: an outline, the points
//! behind it, their heights and colours); what the run learns of the object behind an obstacle —
//! what its push tests decided, whether the robot moved it, whether it tipped, whether it came by
//! itself, where it was seen from — outlives any one detection and stays with the object's id in a
//! [`Knowledge`]. An obstacle a later look finds again takes the id (see
//! [`super::world::WorldModel::remember`]), and with it everything known of the object.
//!
//! [`Prism`]: nudge_perception::Prism

use nalgebra::Point2;
use nudge_perception::ObjectId;
use nudge_perception::grid::Verdict;
use std::collections::BTreeMap;

/// Looks taken this close together (m) were taken from one place: a tenth of the body's stride
/// the walk controller ends a walk within (its goal tolerance is 5 cm).
pub(crate) const SAME_PLACE: f64 = 0.05;

/// What a push test decided of an object, and which test it was.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Judgement {
    /// Static or movable.
    pub verdict: Verdict,
    /// The number of the push test behind the verdict (the run's `push_tests` at the time).
    pub push_test: u32,
}

/// How the robot has moved an object.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum Moved {
    /// The robot never moved it.
    #[default]
    Never,
    /// A confirmed push moved it, and no look has shown it since: its footprint is a prediction (the
    /// object may have turned as it slid), which the next sight of it replaces.
    Predicted,
    /// A confirmed push moved it, and a look has shown it since.
    Seen,
}

/// Everything the run has learnt of one object besides its latest outline.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Knowledge {
    /// What its push tests decided last (`None`: never decided).
    pub judgement: Option<Judgement>,
    /// Whether, and how lately, the robot moved it by a push: an object moved is one rigid body of
    /// known height, whose id a later detection overlapping it takes.
    pub moved: Moved,
    /// A push test's stroke stopped on it with its force leaning out of the horizontal: it tipped
    /// under the hand, and is pushed low from then on.
    pub tipped: bool,
    /// A look saw it arrive (an earlier view of the look saw through where it stands, or it stands on
    /// floor the grid saw free): it came while the head turned, by itself or carried, and may be a
    /// person.
    pub arrived: bool,
    /// A later look showed it to be part of another object (a table tested at one end, found whole
    /// later), whose id this is: its verdicts are about that object.
    pub joined: Option<ObjectId>,
    /// The places the looks that showed it were taken from (map frame), no two within
    /// [`SAME_PLACE`].
    pub seen_from: Vec<Point2<f64>>,
    /// When a look's detections last showed it, as robot time let pass
    /// ([`super::watchdog::Watchdog::elapsed`]); `None`: never.
    pub last_detected: Option<f64>,
    /// Objects a push test saw part from this one (one obstacle to perception, two to the push):
    /// they are never one obstacle again, whatever a look shows of them.
    pub apart_from: Vec<ObjectId>,
}

impl Knowledge {
    /// Whether a push test decided the object static.
    pub fn settled(&self) -> bool {
        self.judged(Verdict::Static)
    }

    /// Whether a push test decided the object movable.
    pub fn movable(&self) -> bool {
        self.judged(Verdict::Movable)
    }

    /// Whether the last push test that decided anything of the object decided `verdict`.
    pub fn judged(&self, verdict: Verdict) -> bool {
        self.judgement.is_some_and(|j| j.verdict == verdict)
    }

    /// Whether the robot ever moved the object by a push.
    pub fn ever_moved(&self) -> bool {
        self.moved != Moved::Never
    }

    /// Whether the object's footprint is where a push left it by prediction, not yet seen there.
    pub fn predicted(&self) -> bool {
        self.moved == Moved::Predicted
    }

    /// Whether nobody has tested, moved or judged the object: no push test's verdict, never moved by
    /// the robot. Only such an obstacle can be a mistake of perception's (a smear, a piece of
    /// something else) to forget or join to another.
    pub fn untouched(&self) -> bool {
        self.judgement.is_none() && !self.ever_moved()
    }

    /// Records that a look showed the object where it is now: a footprint predicted by a push is
    /// replaced by what the look saw.
    pub fn seen_again(&mut self) {
        if self.moved == Moved::Predicted {
            self.moved = Moved::Seen;
        }
    }

    /// Records that a look taken at `place` showed the object (once per place).
    pub fn seen_from_place(&mut self, place: Point2<f64>) {
        if !self
            .seen_from
            .iter()
            .any(|p| (p - place).norm() < SAME_PLACE)
        {
            self.seen_from.push(place);
        }
    }
}

/// What the run knows of every object it has numbered, by id: an id is never handed out twice in a
/// run, so what is known of a forgotten object never passes to a new one.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Objects(BTreeMap<ObjectId, Knowledge>);

/// Knowledge of an object the run has learnt nothing of.
static NOTHING_KNOWN: Knowledge = Knowledge {
    judgement: None,
    moved: Moved::Never,
    tipped: false,
    arrived: false,
    joined: None,
    seen_from: Vec::new(),
    last_detected: None,
    apart_from: Vec::new(),
};

impl Objects {
    /// What is known of object `id` (nothing, for an id never met).
    pub fn get(&self, id: ObjectId) -> &Knowledge {
        self.0.get(&id).unwrap_or(&NOTHING_KNOWN)
    }

    /// What is known of object `id`, to add to.
    pub fn learn(&mut self, id: ObjectId) -> &mut Knowledge {
        self.0.entry(id).or_default()
    }

    /// Records a push test's `verdict` of object `id`, replacing any before it.
    pub fn judge(&mut self, id: ObjectId, verdict: Verdict, push_test: u32) {
        self.learn(id).judgement = Some(Judgement { verdict, push_test });
    }

    /// Records that a confirmed push moved object `id`: its footprint is a prediction until seen.
    pub fn pushed(&mut self, id: ObjectId) {
        self.learn(id).moved = Moved::Predicted;
    }

    /// Records that object `absorbed` is part of object `into`: it was seen from wherever either
    /// was, and what was predicted of its footprint is replaced by the whole that a look showed.
    pub fn join(&mut self, absorbed: ObjectId, into: ObjectId) {
        let places = std::mem::take(&mut self.learn(absorbed).seen_from);
        let part = self.learn(absorbed);
        part.seen_again();
        part.joined = Some(into);
        let whole = self.learn(into);
        for p in places {
            whole.seen_from_place(p);
        }
    }

    /// Records that a push test moved object `moved` and left `rest` standing, where perception saw
    /// one obstacle: `rest` is a new object, seen from where `moved` was and when, and that arrived
    /// if it did, but none of its tests, verdicts or pushes are the rest's (they were of what the
    /// hand moved). The two are never one obstacle again.
    pub fn part(&mut self, moved: ObjectId, rest: ObjectId) {
        let whole = self.get(moved);
        let part = Knowledge {
            seen_from: whole.seen_from.clone(),
            last_detected: whole.last_detected,
            arrived: whole.arrived,
            apart_from: vec![moved],
            ..Knowledge::default()
        };
        self.0.insert(rest, part);
        self.learn(moved).apart_from.push(rest);
    }

    /// Whether a push test saw objects `a` and `b` move apart.
    pub fn apart(&self, a: ObjectId, b: ObjectId) -> bool {
        self.get(a).apart_from.contains(&b)
    }

    /// Each object a later look found part of another, with the id of the one it joined.
    pub fn joins(&self) -> BTreeMap<ObjectId, ObjectId> {
        self.0
            .iter()
            .filter_map(|(id, k)| Some((*id, k.joined?)))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_verdict_replaces_the_one_before_and_an_untested_object_has_none() {
        // Invariant: an object carries at most one verdict, the last push test's; one never judged
        // or moved is untouched.
        let mut objects = Objects::default();
        let id = ObjectId(3);
        assert!(objects.get(id).untouched());
        objects.judge(id, Verdict::Static, 1);
        assert!(objects.get(id).settled() && !objects.get(id).movable());
        objects.judge(id, Verdict::Movable, 2);
        assert!(objects.get(id).movable() && !objects.get(id).settled());
        assert_eq!(objects.get(id).judgement.map(|j| j.push_test), Some(2));
        assert!(!objects.get(id).untouched());
        assert!(objects.get(ObjectId(4)).untouched());
    }

    #[test]
    fn a_pushed_footprint_is_a_prediction_until_a_look_shows_it() {
        // Invariant: a push makes the object moved and its footprint predicted; a sight of it keeps
        // it moved (one rigid body) and ends the prediction; nothing else makes it moved.
        let mut objects = Objects::default();
        let id = ObjectId(1);
        objects.learn(id).seen_again();
        assert_eq!(objects.get(id).moved, Moved::Never);
        objects.pushed(id);
        assert!(objects.get(id).predicted() && objects.get(id).ever_moved());
        assert!(!objects.get(id).untouched());
        objects.learn(id).seen_again();
        assert!(!objects.get(id).predicted() && objects.get(id).ever_moved());
    }

    #[test]
    fn a_joined_part_hands_its_places_to_the_whole_once_each() {
        // Invariant: after a join the whole was seen from every place either part was, no place
        // twice, and the part names the whole it joined.
        let mut objects = Objects::default();
        let (part, whole) = (ObjectId(7), ObjectId(8));
        objects.learn(part).seen_from_place(Point2::new(0.0, 0.0));
        objects.learn(part).seen_from_place(Point2::new(2.0, 0.0));
        objects.learn(whole).seen_from_place(Point2::new(0.01, 0.0));
        objects.pushed(part);
        objects.join(part, whole);
        assert_eq!(objects.get(whole).seen_from.len(), 2);
        assert!(objects.get(part).seen_from.is_empty());
        assert!(!objects.get(part).predicted());
        assert_eq!(objects.joins().get(&part), Some(&whole));
        assert_eq!(objects.joins().len(), 1);
    }

    #[test]
    fn what_a_push_left_standing_keeps_what_was_seen_but_no_verdict_and_stays_apart() {
        // Invariant: the part a push test split off keeps where and when the obstacle was seen, none
        // of its verdicts or pushes, and the two parts are apart both ways.
        let mut objects = Objects::default();
        let (moved, rest) = (ObjectId(2), ObjectId(9));
        objects.learn(moved).seen_from_place(Point2::new(1.0, 1.0));
        objects.learn(moved).last_detected = Some(4.0);
        objects.judge(moved, Verdict::Movable, 1);
        objects.pushed(moved);
        objects.part(moved, rest);
        let left = objects.get(rest);
        assert_eq!(left.seen_from, vec![Point2::new(1.0, 1.0)]);
        assert_eq!(left.last_detected, Some(4.0));
        assert!(left.untouched());
        assert!(objects.apart(moved, rest) && objects.apart(rest, moved));
        assert!(!objects.apart(moved, ObjectId(3)));
        assert!(objects.get(moved).movable());
    }
}
