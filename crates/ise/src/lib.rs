//! areo-ise: the Incremental Search Engine of TEMPEST (Tompkins, Stentz & Wettergreen
//! 2004).
//!
//! A general-purpose discrete-space search engine that knows nothing about rovers or
//! Mars. A user describes a problem as a [`Domain`]: discrete states (IPARMS), labels
//! carrying fine path quantities (DPARMS) grouped into resolution classes by a key,
//! backward transitions with non-negative costs and local constraints, a dominance
//! test, a global constraint, a start test and an admissible heuristic. [`Search`]
//! then searches backwards from one or many [`Goal`]s (each with an initial cost) to
//! the start, in [`Mode::BestPathCost`] (BESTPCOST) or [`Mode::BestDparms`]
//! (BESTDPARMS), and repairs its graph incrementally when costs change
//! ([`Search::update`]), the goals change ([`Search::set_goals`]) or the start moves
//! ([`Search::start_moved`]).
//!
//! Memory grows with the states touched (a hash table of states, an arena of labels);
//! nothing is allocated for the untouched space, and labels that no longer serve a
//! purpose (beaten, or removed by a repair) are reclaimed ([`Search::compact`]). With
//! many labels per state and dominance, a label is tested only against those of its
//! dominance group (Pareto labels per time class, say). With no DPARMS and no
//! constraints the answers equal A*'s.
//!
//! ```
//! use areo_ise::{Goal, Mode, Search, grid::Grid};
//!
//! // A 5×3 grid with a wall; plan from (0, 0) to (4, 0), then block the way and repair.
//! let mut grid = Grid::new(5, 3);
//! for y in 0..2 {
//!     grid.set_free(grid.cell(2, y), false);
//! }
//! grid.set_start(grid.cell(0, 0));
//! let goal = Goal { state: grid.cell(4, 0), label: (), cost: 0.0 };
//! let mut search = Search::new(&grid, [goal], Mode::BestPathCost);
//! let plan = search.plan(&grid);
//! // Round the foot of the wall without cutting corners: four straight steps and two
//! // diagonals.
//! assert!((plan.cost - (4.0 + 2.0 * std::f64::consts::SQRT_2)).abs() < 1e-9);
//!
//! grid.set_free(grid.cell(2, 2), false); // the wall now closes the map
//! search.update(&grid, &grid.changed_states(grid.cell(2, 2), true));
//! assert!(search.plan(&grid).path.is_none());
//! ```
//!
//! Architecture invariant: areo-ise depends on no other areo crate and does no I/O
//! (the Moving AI parsers take text).

mod arena;
mod domain;
mod group_table;
mod open;
mod search;
mod state_table;

pub mod grid;

pub use crate::{
    domain::{Domain, Goal, Predecessor},
    search::{MEMORY_CHECK_EVERY, Mode, PathStep, Plan, Search, Stats},
};
