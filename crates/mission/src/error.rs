use crate::action_model::Binding;

/// Everything that can go wrong in areo-mission.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A planner or world parameter is out of range.
    #[error("`{field}`: {message}")]
    Config {
        /// The field.
        field: &'static str,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// No plan was found; `binding` names the constraint that prevents one (found by
    /// relaxing constraints one at a time).
    #[error("unreachable: no plan reaches the goal; binding constraint: {message}")]
    Unreachable {
        /// The binding constraint.
        binding: Binding,
        /// A description (saying so when the verdict is not `proven`).
        message: String,
        /// Whether the verdict is exact: the cause does not depend on time (slope,
        /// blocked ground, a goal window past the horizon), or the search that found no
        /// plan was exact at the actions' quanta — every class one instant, energy
        /// exact, for arrival at the goal instants of every `goal_times` up to the
        /// configured one. False when the actions are unquantised: time classes then
        /// merge instants, and other settings may find a plan.
        proven: bool,
    },
    /// A planned action could not be predicted forward (the plan's battery and times
    /// are computed by replaying it): the search and the forward model disagree, and
    /// the plan is not returned rather than returned with a step left out.
    #[error("the plan's step {step} ({action}) at cell {cell} could not be replayed forward: {binding}")]
    Replay {
        /// The step's index in the plan.
        step: usize,
        /// The action, as text.
        action: String,
        /// The cell it starts from.
        cell: u32,
        /// What refused it.
        binding: String,
    },
    /// A planning call reached [`crate::PlannerConfig::max_expansions`] before it had an
    /// answer: neither a plan nor a proof that none exists.
    #[error(
        "the searches stopped after the work of {expansions} label expansions (long Pareto fronts' comparisons included), the most one planning call may do ({limit}): no plan, and no proof that none exists"
    )]
    WorkLimit {
        /// Work done by the call, in expansions ([`crate::ExpansionMeter::work`]).
        expansions: u64,
        /// The limit.
        limit: u64,
    },
    /// A planning call's search graphs reached [`crate::PlannerConfig::max_search_bytes`]
    /// before it had an answer.
    #[error(
        "the searches stopped when their graphs held {:.2} GiB, the most one planning call may hold ({:.2} GiB): no plan, and no proof that none exists",
        *bytes as f64 / (1u64 << 30) as f64,
        *limit as f64 / (1u64 << 30) as f64
    )]
    MemoryLimit {
        /// Bytes the graphs held when the search stopped.
        bytes: u64,
        /// The limit, bytes.
        limit: u64,
    },
    /// The terrain could not be processed.
    #[error(transparent)]
    Terrain(#[from] areo_terrain::Error),
}

/// `Result` with this crate's [`enum@Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;
