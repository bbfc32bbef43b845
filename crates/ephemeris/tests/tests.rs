//! areo-ephemeris integration tests: the published Mars24 worked examples, round trips
//! and the seasonal and diurnal facts every Mars ephemeris must reproduce.

mod bodies;
mod earth;
mod events;
mod seasons;
mod worked_examples;
