//! When a fault acts: a trigger, and how many times.

use std::cell::{Cell, RefCell};
use std::rc::Rc;

use super::StateProbe;

/// When a fault may act. Every trigger is deterministic: the same run meets it at the same point.
#[derive(Clone, Debug)]
pub enum Trigger {
    /// From the start.
    Always,
    /// From this robot time on (s, the wrapped robot's clock).
    FromTime(f64),
    /// From the `n`-th chance on (1-based): the `n`-th call through which the fault can act.
    FromChance(u64),
    /// While the executive is in `state` on its `visit`-th entry (1-based), as `probe` sees it.
    InState {
        /// Follows the executive's state; pass a clone of it to the runner as (part of) its observer.
        probe: StateProbe,
        /// The state's name, as [`crate::State::name`] gives it.
        state: &'static str,
        /// Which entry into the state (1: the first).
        visit: u32,
    },
}

/// The first time a fault acted.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Firing {
    /// Robot time (s, the wrapped robot's clock).
    pub stamp: f64,
    /// The executive's state then, when the trigger follows it.
    pub state: Option<&'static str>,
}

/// A trigger and how many times the fault may act once it holds. A decorator asks
/// [`FaultWindow::fires`] at every chance its fault has (a capture, a wrist reading, a status poll);
/// the window counts the chances and the shots, and remembers the first.
///
/// Clones share one count: a test keeps a clone to watch the fault while the decorator owns the
/// robot. Interior mutability, because [`crate::robot::Clock::now`] takes `&self` and a clock fault
/// acts there too.
#[derive(Clone, Debug)]
pub struct FaultWindow(Rc<Counts>);

#[derive(Debug)]
struct Counts {
    trigger: Trigger,
    shots: Option<u32>,
    skip: Cell<u64>,
    chances: Cell<u64>,
    held: Cell<u64>,
    fired: Cell<u32>,
    first: RefCell<Option<Firing>>,
}

impl FaultWindow {
    /// Acts at every chance while `trigger` holds (a sensor that stays broken).
    pub fn every(trigger: Trigger) -> Self {
        Self::new(trigger, None)
    }

    /// Acts once, at the first chance while `trigger` holds (a glitch, a lost message).
    pub fn once(trigger: Trigger) -> Self {
        Self::new(trigger, Some(1))
    }

    fn new(trigger: Trigger, shots: Option<u32>) -> Self {
        Self(Rc::new(Counts {
            trigger,
            shots,
            skip: Cell::new(0),
            chances: Cell::new(0),
            held: Cell::new(0),
            fired: Cell::new(0),
            first: RefCell::new(None),
        }))
    }

    /// The same window letting the first `n` chances its trigger holds for pass: a fault deeper
    /// into a state (the 400th call of a push test falls in its stroke).
    pub fn skip(self, n: u64) -> Self {
        self.0.skip.set(n);
        self
    }

    /// The trigger.
    pub fn trigger(&self) -> &Trigger {
        &self.0.trigger
    }

    /// Whether the trigger holds at robot time `now`, without counting a chance.
    pub fn holds(&self, now: f64) -> bool {
        let w = &self.0;
        match &w.trigger {
            Trigger::Always => true,
            Trigger::FromTime(t) => now >= *t,
            Trigger::FromChance(n) => w.chances.get() >= *n,
            Trigger::InState {
                probe,
                state,
                visit,
            } => probe.is_in(state, *visit),
        }
    }

    /// Counts a chance at robot time `now` and says whether the fault acts on it: the trigger holds
    /// and shots are left. The first shot is remembered.
    pub fn fires(&self, now: f64) -> bool {
        let w = &self.0;
        w.chances.set(w.chances.get() + 1);
        let spent = w.shots.is_some_and(|n| w.fired.get() >= n);
        if spent || !self.holds(now) {
            return false;
        }
        w.held.set(w.held.get() + 1);
        if w.held.get() <= w.skip.get() {
            return false;
        }
        w.fired.set(w.fired.get() + 1);
        w.first.borrow_mut().get_or_insert(Firing {
            stamp: now,
            state: match &w.trigger {
                Trigger::InState { probe, .. } => probe.current(),
                _ => None,
            },
        });
        true
    }

    /// How many times the fault acted.
    pub fn fired(&self) -> u32 {
        self.0.fired.get()
    }

    /// When the fault first acted; `None` when it never got its chance.
    pub fn first(&self) -> Option<Firing> {
        *self.0.first.borrow()
    }

    /// True once the fault can no longer act: its shots are spent, or its trigger is a state's visit
    /// that is over. A run whose fault expired without acting goes on as it would have without the
    /// decorator: a decorator changes nothing until its window fires.
    pub fn expired(&self) -> bool {
        let w = &self.0;
        let spent = w.shots.is_some_and(|n| w.fired.get() >= n);
        let over = match &w.trigger {
            Trigger::InState {
                probe,
                state,
                visit,
            } => probe.visit_over(state, *visit),
            _ => false,
        };
        spent || over
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_window_fires_from_its_trigger_as_often_as_its_shots_allow() {
        // Invariant: a once-window fires at the first chance its trigger holds and never again; an every-window at each such chance; chances before the trigger count but do not fire; a skip lets that many chances in the trigger pass first; the first firing is remembered.
        let once = FaultWindow::once(Trigger::FromTime(1.0));
        assert!(!once.fires(0.5));
        assert!(once.fires(1.0));
        assert!(!once.fires(1.5));
        assert_eq!(once.fired(), 1);
        assert_eq!(once.first().map(|f| f.stamp), Some(1.0));
        let every = FaultWindow::every(Trigger::FromChance(2));
        assert!(!every.fires(0.0));
        assert!(every.fires(0.0));
        assert!(every.fires(0.0));
        assert_eq!(every.fired(), 2);
        let third = FaultWindow::once(Trigger::FromTime(1.0)).skip(2);
        assert!(!third.fires(0.5));
        assert!(!third.fires(1.0));
        assert!(!third.fires(1.0));
        assert!(third.fires(1.0));
        assert!(!third.fires(1.0));
    }
}
