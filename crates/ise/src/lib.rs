//! areo-ise: the Incremental Search Engine of TEMPEST.
//!
//! A general-purpose discrete-space search engine that knows nothing about rovers or
//! Mars: a user-defined domain supplies discrete states (IPARMS), fine-grained path
//! quantities carried by labels (DPARMS), backward transitions with costs and local
//! feasibility, dominance and resolution pruning, and an admissible heuristic. The
//! engine finds least-cost (BESTPCOST) or best-by-order (BESTDPARMS) paths under global
//! constraints and repairs them incrementally when costs change or the start moves.
//!
//! Architecture invariant: areo-ise depends on no other areo crate and does no I/O.
//!
//! Status: the crate is created by the workspace foundation; the engine lands with the
//! ISE issue.
