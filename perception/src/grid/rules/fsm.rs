//! Lopez-Perez et al.'s per-cell finite state machine (Sect. 2.2, Fig. 4) and its replanning flag.
//!
//! Four labels and two inputs per frame: f₁ = "a return lies on the cell", f₂ = "the cell is inside
//! the visible polygon". f₁ = 1 forces f₂ = 0, so the input is one of three [`LpInput`]s and the
//! impossible (1, 1) cannot be written. The replanning flag f_rp is raised when a cell on the planned
//! path goes *non explored → steady obstacle* or *explored → mobile obstacle*.
//!
//! The grid uses the richer Tamura classes; [`LpState::of`] maps them onto these four labels, and the
//! grid raises its flag on every change into an obstacle class ([`raises_replan`]): Stationary and
//! Moving as the brief asks, and Movable too (something coming to rest on the path blocks it just the
//! same). This contains both of Lopez-Perez's edges (tested below).

use super::super::class::CellClass;

/// A cell label of Lopez-Perez's map.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LpState {
    /// Never observed.
    NonExplored,
    /// Observed free.
    Explored,
    /// A steady (static) obstacle.
    Steady,
    /// A mobile obstacle.
    Mobile,
}

/// One frame's observation of a cell: (f₁, f₂).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum LpInput {
    /// (0, 0): neither returned nor inside the visible polygon.
    Unobserved,
    /// (0, 1): inside the visible polygon, no return.
    SeenFree,
    /// (1, 0): a return lies on the cell.
    Occupied,
}

/// The result of one transition.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LpTransition {
    /// The next label.
    pub next: LpState,
    /// Whether this edge raises the replanning flag when the cell is on the planned path.
    pub replan_on_path: bool,
}

impl LpState {
    /// The Lopez-Perez label of a grid class (movable counts as a steady obstacle for their map).
    pub fn of(class: CellClass) -> Self {
        match class {
            CellClass::Unknown => LpState::NonExplored,
            CellClass::Free => LpState::Explored,
            CellClass::Stationary | CellClass::Movable => LpState::Steady,
            CellClass::Moving => LpState::Mobile,
        }
    }
}

/// Fig. 4: the next label of a cell given its label and this frame's observation.
///
/// A return on a never-explored cell is a steady obstacle (nothing says it moved); a return on a cell
/// known free is a mobile obstacle (it was not there before); an obstacle cell seen free becomes
/// explored; unobserved cells keep their label.
pub fn transition(state: LpState, input: LpInput) -> LpTransition {
    use LpInput::*;
    use LpState::*;
    let (next, replan_on_path) = match (state, input) {
        (s, Unobserved) => (s, false),
        (_, SeenFree) => (Explored, false),
        (NonExplored, Occupied) => (Steady, true),
        (Explored, Occupied) => (Mobile, true),
        (Steady, Occupied) => (Steady, false),
        (Mobile, Occupied) => (Mobile, false),
    };
    LpTransition {
        next,
        replan_on_path,
    }
}

/// The grid's replanning rule: a watched cell changing into an obstacle class.
pub fn raises_replan(old: CellClass, new: CellClass) -> bool {
    old != new && new.is_obstacle()
}

#[cfg(test)]
mod tests {
    use super::*;
    use LpInput::*;
    use LpState::*;

    #[test]
    fn every_edge_of_the_transition_table() {
        // Invariant: the 12 edges of Fig. 4 (4 labels × 3 inputs), with f_rp on exactly two of them.
        let table = [
            (NonExplored, Unobserved, NonExplored, false),
            (NonExplored, SeenFree, Explored, false),
            (NonExplored, Occupied, Steady, true),
            (Explored, Unobserved, Explored, false),
            (Explored, SeenFree, Explored, false),
            (Explored, Occupied, Mobile, true),
            (Steady, Unobserved, Steady, false),
            (Steady, SeenFree, Explored, false),
            (Steady, Occupied, Steady, false),
            (Mobile, Unobserved, Mobile, false),
            (Mobile, SeenFree, Explored, false),
            (Mobile, Occupied, Mobile, false),
        ];
        for (s, i, next, rp) in table {
            assert_eq!(
                transition(s, i),
                LpTransition {
                    next,
                    replan_on_path: rp
                },
                "{s:?} --{i:?}-->"
            );
        }
    }

    #[test]
    fn the_grid_replans_on_both_lopez_perez_edges() {
        // Invariant: whenever Fig. 4 raises f_rp between grid classes, the grid's rule does too.
        for old in CellClass::ALL {
            for new in CellClass::ALL {
                let t = transition(LpState::of(old), LpInput::Occupied);
                if t.replan_on_path && LpState::of(new) == t.next && LpState::of(old) != t.next {
                    assert!(raises_replan(old, new), "{old:?} -> {new:?}");
                }
            }
        }
        assert!(raises_replan(CellClass::Unknown, CellClass::Stationary));
        assert!(raises_replan(CellClass::Free, CellClass::Moving));
        assert!(!raises_replan(CellClass::Moving, CellClass::Moving));
        assert!(!raises_replan(CellClass::Unknown, CellClass::Free));
        assert!(!raises_replan(CellClass::Stationary, CellClass::Free));
    }
}
