//! Seeing which state the executive is in, from a robot decorator.

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::rc::Rc;

use crate::machine::Edge;
use crate::record::Observer;
use crate::state::State;

#[derive(Debug, Default)]
struct Visits {
    current: Option<&'static str>,
    entries: BTreeMap<&'static str, u32>,
}

/// The executive's current state and how many times it entered each, shared between an observer
/// (the probe itself, handed to the runner) and the fault windows that read it
/// ([`super::Trigger::InState`]). The runner reports a transition before it executes the new state's
/// commands, so every adapter call the state makes sees the probe in that state.
///
/// A transition from a state to itself (a push plan becoming a walk) is not a new entry.
#[derive(Clone, Debug, Default)]
pub struct StateProbe(Rc<RefCell<Visits>>);

impl StateProbe {
    /// A probe that has seen nothing yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// The state the executive is in, once the run has started.
    pub fn current(&self) -> Option<&'static str> {
        self.0.borrow().current
    }

    /// Whether the executive is in `state` on its `visit`-th entry.
    pub fn is_in(&self, state: &str, visit: u32) -> bool {
        let v = self.0.borrow();
        v.current == Some(state) && v.entries.get(state) == Some(&visit)
    }

    /// Whether the executive has left its `visit`-th entry into `state`.
    pub fn visit_over(&self, state: &str, visit: u32) -> bool {
        let v = self.0.borrow();
        let entries = v.entries.get(state).copied().unwrap_or(0);
        entries > visit || (entries == visit && v.current != Some(state))
    }
}

impl Observer for StateProbe {
    fn transition(&mut self, _stamp: f64, _from: Option<&State>, _edge: Edge, to: &State) {
        let mut v = self.0.borrow_mut();
        let name = to.name();
        if v.current != Some(name) {
            *v.entries.entry(name).or_insert(0) += 1;
            v.current = Some(name);
        }
    }
}
