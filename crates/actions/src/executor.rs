//! The plan executor: runs a plan's modules one after another on the LSR-1 model over
//! the terrain until the task is complete or a constraint is violated, and records
//! what the fitness needs.
//!
//! Constraints: every pose of every module is evaluated in full by areo-rover (slip,
//! loss of contact, motor saturation, tip-over, kinematics — leaving the map is a
//! kinematics failure); the stability margin must stay above a hard floor; the body
//! (a box) must not touch a rock (parry3d). [A] The body box is 0.60 × 0.40 × 0.12 m
//! centred on the rocker pivots (belly 0.26 m up: rocks up to one wheel diameter pass
//! under it); it turns with the heading, and its pitch and roll are ignored for the
//! collision test (a few centimetres at the box's ends on the slopes driven). A grasp
//! reaches down to the nearest sample in the arm's workspace by inverse kinematics and
//! back (areo-rover's `Motion::run`). A module with nothing to act on (a grasp with
//! nothing in reach, a release with an empty gripper, an arm move out of reach, a turn
//! to a sample with none near) violates no constraint: it changes nothing but still
//! spends its time and hotel energy (`Motion::idle`), and the plan goes on.

use areo_rover::evaluation::{Conditions, Evaluator, Violation};
use areo_rover::forces::ForceFailure;
use areo_rover::motion::{Module, Motion, MotionFailure, RoverState, SampleSite, Stopped};
use areo_terrain::Ground;
use parry3d::math::{Pose, Rotation, Vector};
use parry3d::query::intersection_test;
use parry3d::shape::{Ball, Cuboid};
use serde::{Deserialize, Serialize};

use crate::task::Task;

/// Execution settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ExecConfig {
    /// Friction coefficient μ.
    pub mu: f64,
    /// Hard floor of the stability margin S (0..1): below it the plan fails.
    pub stability_floor: f64,
    /// Body box half extents (forward, left, up), m.
    pub body_half_m: (f64, f64, f64),
}

impl Default for ExecConfig {
    fn default() -> ExecConfig {
        ExecConfig { mu: 0.65, stability_floor: 0.20, body_half_m: (0.30, 0.20, 0.06) }
    }
}

/// Why a plan stopped early.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum ExecFailure {
    /// The start pose is not admissible: no plan can run.
    StartPose(Violation),
    /// A module could not run: the physical limit it met (areo-rover's reason, typed).
    Motion(MotionFailure),
    /// The stability margin fell below the floor.
    Stability(f64),
    /// The body hit a rock.
    Collision(usize),
}

impl ExecFailure {
    /// A short name of the kind of failure, for reports: `start_pose`, `tip_over`,
    /// `slip`, `loss_of_contact`, `saturation`, `kinematics`, `battery`, `stability`,
    /// `collision` (the arm's and gripper's no-ops, which are not failures, as
    /// `module`).
    pub fn kind(&self) -> &'static str {
        match self {
            ExecFailure::StartPose(_) => "start_pose",
            ExecFailure::Motion(MotionFailure::Violation(v)) => match v {
                Violation::TipOver => "tip_over",
                Violation::Forces { failure: ForceFailure::Slip, .. } => "slip",
                Violation::Forces { failure: ForceFailure::LossOfContact, .. } => "loss_of_contact",
                Violation::Forces { failure: ForceFailure::Saturation, .. } => "saturation",
                Violation::Kinematics(_) => "kinematics",
            },
            ExecFailure::Motion(MotionFailure::Battery) => "battery",
            ExecFailure::Motion(MotionFailure::BelowFloor(_)) | ExecFailure::Stability(_) => "stability",
            ExecFailure::Motion(_) => "module",
            ExecFailure::Collision(_) => "collision",
        }
    }
}

impl std::fmt::Display for ExecFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ExecFailure::StartPose(v) => write!(f, "the start pose is not admissible: {v}"),
            ExecFailure::Motion(m) => m.fmt(f),
            ExecFailure::Stability(s) => write!(f, "stability margin {:.0} % below the floor", 100.0 * s),
            ExecFailure::Collision(i) => write!(f, "the body hit rock {i}"),
        }
    }
}

/// One executed module, for reports and plots.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TraceStep {
    /// Table 1 code.
    pub code: u16,
    /// Reference point after the module, m.
    pub x_m: f64,
    /// Reference point after the module, m.
    pub y_m: f64,
    /// Body reference height after the module, m.
    pub z_m: f64,
    /// Heading after, degrees.
    pub heading_deg: f64,
    /// Body pitch after, degrees.
    pub pitch_deg: f64,
    /// Least stability margin during the module (0..1), if it moved anything.
    pub stability: Option<f64>,
    /// Wheel normal loads after the module, N (left front, middle, rear, right …).
    pub wheel_loads_n: [f64; 6],
    /// Battery energy used by the module, Wh.
    pub energy_wh: f64,
    /// How long the module took, s.
    pub duration_s: f64,
    /// The arm's tool (wrist) after the module, body frame (x forward, y left, z up), m.
    pub tool_m: [f64; 3],
    /// Wheel axle positions after the module (x, y, z), m — for the side profile.
    pub wheels: [[f64; 3]; 6],
    /// Largest friction any wheel used over the module's poses (|T|/N, in-plane and
    /// lateral): the least μ the module needs.
    pub friction_used: f64,
}

/// The wheel whose friction (or contact) gave out when a plan stopped on a force
/// limit, read at the last admissible pose: the wheel using the largest share of its
/// normal force as traction there.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WheelLimit {
    /// "left front", "right middle", …
    pub wheel: String,
    /// Its contact point, map frame, m.
    pub contact_m: [f64; 3],
    /// Its contact angle γ, degrees: the ground rising ahead positive (90 a wall ahead).
    pub contact_angle_deg: f64,
    /// Whether the wheel is moving up its contact (γ and the direction of travel of
    /// the same sign) — climbing a wall or slope — rather than down it.
    pub climbing: bool,
    /// Body pitch, degrees (nose up positive).
    pub pitch_deg: f64,
    /// That wheel's |T|/N at the last admissible pose.
    pub friction_used: f64,
    /// The wheel on the steepest ground there (largest |γ|) — the one meeting the wall
    /// or slope that makes the others push or hold — its contact angle, degrees, and
    /// whether it is climbing.
    pub steepest: (String, f64, bool),
}

impl std::fmt::Display for WheelLimit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} wheel at its friction limit (|T|/N = {:.2}, contact angle {:.0}°, at ({:.2}, {:.2}) m) while the {} wheel is {} ground at {:.0}° (body pitch {:.0}°)",
            self.wheel,
            self.friction_used,
            self.contact_angle_deg,
            self.contact_m[0],
            self.contact_m[1],
            self.steepest.0,
            if self.steepest.2 { "climbing" } else { "descending" },
            self.steepest.1.abs(),
            self.pitch_deg
        )
    }
}

/// The executor's state after a module: enough to resume a plan that shares this
/// prefix (a GA child keeps its parent's modules up to the crossover point), or to go
/// on from it with other modules ([`Executor::continue_from`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Checkpoint {
    state: RoverState,
    collected: Vec<bool>,
    samples: usize,
    taken: Vec<usize>,
    stabilities: usize,
    time_s: f64,
    energy_wh: f64,
    peak_friction_ratio: f64,
    peak_saturation: f64,
    distance_to_target_m: f64,
}

impl Checkpoint {
    /// The rover's state: where it stands, its heading, arm, battery and pose.
    pub fn state(&self) -> &RoverState {
        &self.state
    }

    /// Which of the task's samples have been picked up, by index.
    pub fn collected(&self) -> &[bool] {
        &self.collected
    }

    /// Time spent so far, s.
    pub fn time_s(&self) -> f64 {
        self.time_s
    }
}

/// What running a plan did.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Execution {
    /// Modules that ran to their end before the failure or the task's completion.
    pub prefix_len: usize,
    /// The first failure and the index of its module, if any.
    pub failure: Option<(usize, ExecFailure)>,
    /// Fraction of the failing module done.
    pub failure_progress: f64,
    /// The target reached with the samples wanted.
    pub complete: bool,
    /// Distance from the reference point to the target at the end, m.
    pub distance_to_target_m: f64,
    /// Samples collected.
    pub samples: usize,
    /// The task's samples collected, by index into `Task::samples`, in the order they
    /// were grasped.
    pub taken: Vec<usize>,
    /// Least stability margin over the executed modules (1 if none moved).
    pub min_stability: f64,
    /// Mean of the modules' least margins.
    pub mean_stability: f64,
    /// Every module's least margin (for the fitness's Σ h(S_j)).
    pub stabilities: Vec<f64>,
    /// Time, s.
    pub time_s: f64,
    /// Battery energy used, Wh.
    pub energy_wh: f64,
    /// Largest friction used over μ, over all poses (1 = at the slip limit).
    pub peak_friction_ratio: f64,
    /// Largest motor torque over its limit, over all poses (1 = saturated).
    pub peak_saturation: f64,
    /// The executed modules, when asked for.
    pub trace: Vec<TraceStep>,
    /// When the plan stopped on slip, loss of contact or saturation: the wheel that
    /// bound, when asked for (with the trace).
    pub binding: Option<WheelLimit>,
    /// The state after each executed module (index k: after k + 1 modules), kept so
    /// plans sharing a prefix can resume (see [`Executor::resume`]); not serialised.
    #[serde(skip)]
    pub checkpoints: Vec<Checkpoint>,
}

/// Runs plans for one task on one terrain.
pub struct Executor<'a, G: Ground> {
    ground: &'a G,
    evaluator: &'a Evaluator,
    task: &'a Task,
    config: ExecConfig,
    /// Why the start pose is not admissible, if it is not (checked once: every plan
    /// starts there).
    start_problem: Option<Violation>,
}

impl<G: Ground> std::fmt::Debug for Executor<'_, G> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Executor").field("config", &self.config).finish_non_exhaustive()
    }
}

impl<'a, G: Ground + Sync> Executor<'a, G> {
    /// An executor.
    pub fn new(ground: &'a G, evaluator: &'a Evaluator, task: &'a Task, config: ExecConfig) -> Executor<'a, G> {
        let mut ex = Executor { ground, evaluator, task, config, start_problem: None };
        let motion = Motion::new(evaluator, config.mu);
        if let Err(v) = motion.check(ground, &ex.start_state()) {
            ex.start_problem = Some(v);
        }
        ex
    }

    /// Why no plan can start, if the start pose is not admissible.
    pub fn start_problem(&self) -> Option<&Violation> {
        self.start_problem.as_ref()
    }

    /// The settings.
    pub fn config(&self) -> &ExecConfig {
        &self.config
    }

    /// The rover at the task's start.
    pub fn start_state(&self) -> RoverState {
        let (x, y, h) = self.task.start;
        RoverState::new(self.evaluator, x, y, h.to_radians())
    }

    /// Runs `plan`; with `trace`, records every executed module.
    pub fn run(&self, plan: &[Module], trace: bool) -> Execution {
        self.execute(plan, None, trace)
    }

    /// Runs `plan`, whose first `shared` modules are those of the plan `parent` was
    /// the execution of: their effect is taken from `parent`'s checkpoints and only the
    /// rest is executed. The result equals [`Executor::run`]'s.
    pub fn resume(&self, plan: &[Module], parent: &Execution, shared: usize) -> Execution {
        // Only modules before the parent's failure or completion have checkpoints
        // that a different continuation can build on.
        let usable = if parent.complete { parent.prefix_len.saturating_sub(1) } else { parent.prefix_len };
        let k = shared.min(usable).min(parent.checkpoints.len()).min(plan.len());
        if k == 0 {
            return self.execute(plan, None, false);
        }
        self.execute(plan, Some((parent, k)), false)
    }

    /// Runs `plan` from a saved state `at` (a checkpoint of an earlier execution) as if
    /// its modules followed the ones that led there; the result covers only `plan`'s
    /// modules (its `prefix_len`, stabilities and checkpoints count from `at`), with
    /// time, energy, samples and peaks carried on from `at`.
    pub fn continue_from(&self, at: &Checkpoint, plan: &[Module]) -> Execution {
        self.execute_at(plan, Some(at), 0, (&[], &[]), false)
    }

    fn execute(&self, plan: &[Module], from: Option<(&Execution, usize)>, trace: bool) -> Execution {
        match from {
            Some((parent, k)) => {
                let c = &parent.checkpoints[k - 1];
                self.execute_at(
                    plan,
                    Some(c),
                    k,
                    (&parent.stabilities[..c.stabilities], &parent.checkpoints[..k]),
                    trace,
                )
            }
            None => self.execute_at(plan, None, 0, (&[], &[]), trace),
        }
    }

    /// Runs `plan[first..]` from `at` (the start when `None`), with `history` (the
    /// stabilities and checkpoints of the modules before `first`) copied in.
    fn execute_at(
        &self,
        plan: &[Module],
        at: Option<&Checkpoint>,
        first: usize,
        history: (&[f64], &[Checkpoint]),
        trace: bool,
    ) -> Execution {
        let mut motion = Motion::new(self.evaluator, self.config.mu);
        // The floor is checked pose by pose, so a module that first dips below it and
        // later slips is reported as what happened first.
        motion.stability_floor = self.config.stability_floor;
        let mut state = self.start_state();
        let mut collected = vec![false; self.task.samples.len()];
        let mut out = self.empty_execution(&state, plan.len());
        if let Some(problem) = &self.start_problem {
            out.failure = Some((0, ExecFailure::StartPose(*problem)));
            return out;
        }
        if let Some(c) = at {
            state = c.state;
            collected.clone_from(&c.collected);
            out.resume(c, history, first);
        }
        for (i, &module) in plan.iter().enumerate().skip(first) {
            let samples = self.samples_left(&collected);
            let step = match self.run_module(&motion, &state, module, &samples, trace) {
                Ok(step) => step,
                Err(stop) => {
                    let (failure, progress, binding) = *stop;
                    out.failure = Some((i, failure));
                    out.failure_progress = progress;
                    out.binding = binding.or(out.binding);
                    break;
                }
            };
            if let Some(s) = step.min_stability
                && s < self.config.stability_floor
            {
                out.failure = Some((i, ExecFailure::Stability(s)));
                break;
            }
            if let Some(rock) = self.collision(&step.state) {
                out.failure = Some((i, ExecFailure::Collision(rock)));
                break;
            }
            if let Some(k) = step.grasped {
                collected[k] = true;
                out.samples += 1;
                out.taken.push(k);
            }
            let energy = out.add(&step);
            if trace {
                let mut t = self.trace_step(module, &step.state, step.min_stability, energy, &motion);
                t.friction_used = step.max_friction;
                t.duration_s = step.duration_s;
                out.trace.push(t);
            }
            state = step.state;
            out.prefix_len = i + 1;
            out.distance_to_target_m = self.distance(&state);
            out.checkpoints.push(checkpoint(&state, &collected, &out));
            if out.distance_to_target_m <= self.task.target_radius_m && out.samples >= self.task.samples_wanted {
                out.complete = true;
                break;
            }
        }
        if !out.stabilities.is_empty() {
            out.min_stability = out.stabilities.iter().copied().fold(f64::INFINITY, f64::min);
            out.mean_stability = out.stabilities.iter().sum::<f64>() / out.stabilities.len() as f64;
        }
        out
    }

    /// The task's samples not yet `collected`, as the motions see them.
    fn samples_left(&self, collected: &[bool]) -> Vec<SampleSite> {
        (self.task.samples.iter().enumerate())
            .filter(|(k, _)| !collected[*k])
            .map(|(k, s)| SampleSite { id: k, x: s.x_m, y: s.y_m, mass_kg: s.mass_kg })
            .collect()
    }

    /// An execution that has run nothing yet from `state`, with room for `modules`
    /// checkpoints.
    fn empty_execution(&self, state: &RoverState, modules: usize) -> Execution {
        Execution {
            prefix_len: 0,
            failure: None,
            failure_progress: 0.0,
            complete: false,
            distance_to_target_m: self.distance(state),
            samples: 0,
            taken: Vec::new(),
            min_stability: 1.0,
            mean_stability: 1.0,
            stabilities: Vec::new(),
            time_s: 0.0,
            energy_wh: 0.0,
            peak_friction_ratio: 0.0,
            peak_saturation: 0.0,
            trace: Vec::new(),
            binding: None,
            checkpoints: Vec::with_capacity(modules),
        }
    }

    /// Runs one module from `state` with `samples` still on the ground. A module with
    /// nothing to act on violates no constraint, but its time and hotel energy are
    /// spent. `Err`: why the execution stops there, how far into the module, and (with
    /// `trace`, where the forces failed) the wheel limit that bound.
    fn run_module(
        &self,
        motion: &Motion<'_>,
        state: &RoverState,
        module: Module,
        samples: &[SampleSite],
        trace: bool,
    ) -> Result<areo_rover::motion::ModuleRun, Box<(ExecFailure, f64, Option<WheelLimit>)>> {
        match motion.run(self.ground, state, module, samples) {
            Ok(step) => Ok(step),
            Err(Stopped {
                failure:
                    MotionFailure::NoSample
                    | MotionFailure::NotHolding
                    | MotionFailure::ArmReach
                    | MotionFailure::NothingToTurnTo,
                ..
            }) => motion
                .idle(state, module)
                .map_err(|stopped| Box::new((ExecFailure::Motion(stopped.failure), stopped.progress, None))),
            Err(Stopped { failure: MotionFailure::BelowFloor(s), progress, .. }) => {
                Err(Box::new((ExecFailure::Stability(s), progress, None)))
            }
            Err(Stopped { failure, progress, state: last }) => {
                let binding = if trace && matches!(failure, MotionFailure::Violation(Violation::Forces { .. })) {
                    self.binding(&last, module)
                } else {
                    None
                };
                Err(Box::new((ExecFailure::Motion(failure), progress, binding)))
            }
        }
    }

    fn distance(&self, s: &RoverState) -> f64 {
        (self.task.target.0 - s.x).hypot(self.task.target.1 - s.y)
    }

    /// The first rock the body box touches, if any.
    fn collision(&self, state: &RoverState) -> Option<usize> {
        if self.task.rocks.is_empty() {
            return None;
        }
        let pose = state.pose.as_ref()?;
        let (hx, hy, hz) = self.config.body_half_m;
        let body = Cuboid::new(Vector::new(hx as f32, hy as f32, hz as f32));
        // Body x forward = (sin h, cos h) in (east, north): a rotation by π/2 − h about up.
        let yaw = std::f64::consts::FRAC_PI_2 - pose.heading;
        let at = Pose::from_parts(
            Vector::new(pose.body[0] as f32, pose.body[1] as f32, pose.body[2] as f32),
            Rotation::from_rotation_z(yaw as f32),
        );
        self.task.rocks.iter().position(|r| {
            // The rock's cap as a ball of its half-width whose top is the rock's top.
            let radius = (0.5 * r.width_m).max(1e-3);
            // The ground the rock sits on: the lowest of four points just beyond its
            // edge (the map under the rock may already hold the rock itself).
            let reach = 1.1 * radius;
            let base = [(reach, 0.0), (-reach, 0.0), (0.0, reach), (0.0, -reach)]
                .iter()
                .filter_map(|(dx, dy)| self.ground.height(r.x_m + dx, r.y_m + dy))
                .fold(f64::INFINITY, f64::min);
            let base = if base.is_finite() { base } else { self.ground.height(r.x_m, r.y_m).unwrap_or(0.0) };
            let top = base + r.height_m;
            let ball = Ball::new(radius as f32);
            let centre = Pose::translation(r.x_m as f32, r.y_m as f32, (top - radius) as f32);
            intersection_test(&at, &body, &centre, &ball).is_ok_and(|t| t.intersecting)
        })
    }

    fn trace_step(
        &self,
        module: Module,
        state: &RoverState,
        stability: Option<f64>,
        energy_wh: f64,
        motion: &Motion<'_>,
    ) -> TraceStep {
        let eval = motion.check(self.ground, state).ok();
        // A module that moves nothing before the first drive finds the rover with no
        // pose yet: the check just settled it.
        let pose = state.pose.as_ref().or(eval.as_ref().map(|e| &e.pose));
        let mut loads = [0.0; 6];
        let mut wheels = [[0.0; 3]; 6];
        if let Some(e) = &eval {
            for (i, l) in loads.iter_mut().enumerate() {
                *l = e.sides[i / 3].normal_n[i % 3];
            }
        }
        if let Some(p) = pose {
            for (i, w) in wheels.iter_mut().enumerate() {
                *w = p.wheels[i].axle;
            }
        }
        TraceStep {
            code: module.code(),
            x_m: state.x,
            y_m: state.y,
            z_m: pose.map_or(0.0, |p| p.body[2]),
            heading_deg: state.heading.to_degrees(),
            pitch_deg: pose.map_or(0.0, |p| p.pitch.to_degrees()),
            stability,
            wheel_loads_n: loads,
            energy_wh,
            duration_s: 0.0,
            tool_m: state.arm.tool_m,
            wheels,
            friction_used: 0.0,
        }
    }

    /// The wheel closest to its friction limit at `state` (the last admissible pose of
    /// a module that stopped on a force limit) under `module`'s direction of travel.
    fn binding(&self, state: &RoverState, module: Module) -> Option<WheelLimit> {
        // The pose was admissible: the wheel nearest its limit there is the one that
        // gives out a step later.
        let cond = Conditions { mu: self.config.mu, direction: module.direction() };
        let eval = self.evaluator.evaluate(self.ground, state.place(), &state.arm, &cond, state.pose.as_ref()).ok()?;
        let names = ["left front", "left middle", "left rear", "right front", "right middle", "right rear"];
        let ratio = |k: usize| {
            let side = &eval.sides[k / 3];
            let n = side.normal_n[k % 3];
            if n > 1e-9 { side.traction_n[k % 3].abs() / n } else { f64::INFINITY }
        };
        let k = (0..6).max_by(|a, b| ratio(*a).total_cmp(&ratio(*b)))?;
        let gammas: Vec<f64> = eval.pose.left.gamma.iter().chain(&eval.pose.right.gamma).copied().collect();
        let gamma = gammas[k];
        // A turn in place rolls the wheels forward on one side: call it climbing if
        // the ground rises ahead of the wheel.
        let direction = if module.direction() == 0.0 { 1.0 } else { module.direction() };
        let j = (0..6).max_by(|a, b| gammas[*a].abs().total_cmp(&gammas[*b].abs()))?;
        Some(WheelLimit {
            wheel: names[k].to_string(),
            contact_m: eval.pose.wheels[k].contact,
            contact_angle_deg: gamma.to_degrees(),
            climbing: gamma * direction > 0.0,
            pitch_deg: eval.pose.pitch.to_degrees(),
            friction_used: ratio(k),
            steepest: (names[j].to_string(), gammas[j].to_degrees(), gammas[j] * direction > 0.0),
        })
    }
}

impl Execution {
    /// Adds an executed module's time, energy, peaks (friction as a share of the
    /// friction available where it was used) and stability; returns its net energy, Wh.
    fn add(&mut self, step: &areo_rover::motion::ModuleRun) -> f64 {
        let energy = step.energy.net_wh();
        self.time_s += step.duration_s;
        self.energy_wh += energy;
        self.peak_friction_ratio = self.peak_friction_ratio.max(step.max_friction_share);
        self.peak_saturation = self.peak_saturation.max(step.max_saturation);
        if let Some(s) = step.min_stability {
            self.stabilities.push(s);
        }
        energy
    }

    /// Takes up where checkpoint `c` left off: its samples, time, energy, peaks and
    /// distance, and `history` (the stabilities and checkpoints of the `first` modules
    /// before it).
    fn resume(&mut self, c: &Checkpoint, history: (&[f64], &[Checkpoint]), first: usize) {
        self.samples = c.samples;
        self.taken = c.taken.clone();
        self.stabilities.extend_from_slice(history.0);
        self.time_s = c.time_s;
        self.energy_wh = c.energy_wh;
        self.peak_friction_ratio = c.peak_friction_ratio;
        self.peak_saturation = c.peak_saturation;
        self.distance_to_target_m = c.distance_to_target_m;
        self.checkpoints.extend_from_slice(history.1);
        self.prefix_len = first;
    }
}

fn checkpoint(state: &RoverState, collected: &[bool], out: &Execution) -> Checkpoint {
    Checkpoint {
        state: *state,
        collected: collected.to_vec(),
        samples: out.samples,
        taken: out.taken.clone(),
        stabilities: out.stabilities.len(),
        time_s: out.time_s,
        energy_wh: out.energy_wh,
        peak_friction_ratio: out.peak_friction_ratio,
        peak_saturation: out.peak_saturation,
        distance_to_target_m: out.distance_to_target_m,
    }
}
