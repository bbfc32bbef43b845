//! areo-ise integration tests: Moving AI optimal lengths, brute-force references on
//! time-expanded and battery domains, multi-goal seeding, and re-planning equal to
//! planning from scratch.

mod brute;
mod domains;
mod movingai;
mod multigoal;
mod replan;
