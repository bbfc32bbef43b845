//! A time-expanded domain and a battery domain: ISE against brute-force Dijkstra over
//! the fully enumerated state space, in both modes, including "no feasible path".

use areo_ise::{Domain, Goal, Mode, Predecessor, Search};

use crate::brute::dijkstra;

/// A small deterministic generator so the instances need no RNG crate.
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        self.0 >> 33
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

const MOVES: [(i32, i32); 5] = [(0, 0), (1, 0), (-1, 0), (0, 1), (0, -1)];

/// x, y, t with wait moves; each cell has a time-varying cost and blocked times.
#[derive(Debug, Clone)]
struct TimeGrid {
    w: i32,
    h: i32,
    horizon: u32,
    blocked: Vec<bool>, // [t][cell]
    cost: Vec<f64>,     // [t][cell], cost of being in the cell at t (paid on arrival)
    start: u32,
    /// Expansions made, and how many the caller allows ([`Domain::exhausted`]).
    spent: std::cell::Cell<u64>,
    allowed: u64,
}

impl TimeGrid {
    fn random(seed: u64, w: i32, h: i32, horizon: u32, block_pct: u64) -> TimeGrid {
        let mut r = Lcg(seed);
        let n = (w * h) as usize * (horizon as usize + 1);
        let blocked = (0..n).map(|_| r.below(100) < block_pct).collect();
        let cost = (0..n).map(|_| 1.0 + r.below(4) as f64).collect();
        TimeGrid { w, h, horizon, blocked, cost, start: 0, spent: Default::default(), allowed: u64::MAX }
    }
    fn idx(&self, cell: u32, t: u32) -> usize {
        t as usize * (self.w * self.h) as usize + cell as usize
    }
    fn moved(&self, cell: u32, m: usize, sign: i32) -> Option<u32> {
        let (x, y) = ((cell as i32) % self.w, (cell as i32) / self.w);
        let (nx, ny) = (x + sign * MOVES[m].0, y + sign * MOVES[m].1);
        (nx >= 0 && ny >= 0 && nx < self.w && ny < self.h).then(|| (ny * self.w + nx) as u32)
    }
    fn free(&self, cell: u32, t: u32) -> bool {
        cell == self.start && t == 0 || !self.blocked[self.idx(cell, t)]
    }
    /// Forward transitions from (cell, t).
    fn forward(&self, cell: u32, t: u32) -> Vec<((u32, u32), f64)> {
        if t >= self.horizon || !self.free(cell, t) {
            return vec![];
        }
        (0..5)
            .filter_map(|m| self.moved(cell, m, 1))
            .filter(|&c| self.free(c, t + 1))
            .map(|c| ((c, t + 1), self.cost[self.idx(c, t + 1)]))
            .collect()
    }
    /// The state and time `a` leads from into (`s`, `t`), and the step's cost.
    fn predecessor(&self, s: u32, t: u32, a: u8) -> Option<Predecessor<TimeGrid>> {
        if t == 0 || !self.free(s, t) {
            return None;
        }
        let p = self.moved(s, a as usize, -1)?;
        if !self.free(p, t - 1) {
            return None;
        }
        Some(Predecessor { state: p, label: t - 1, cost: self.cost[self.idx(s, t)] })
    }
    fn manhattan(&self, a: u32, b: u32) -> f64 {
        let (ax, ay) = ((a as i32) % self.w, (a as i32) / self.w);
        let (bx, by) = ((b as i32) % self.w, (b as i32) / self.w);
        f64::from((ax - bx).abs() + (ay - by).abs())
    }
}

impl Domain for TimeGrid {
    type State = u32;
    type Label = u32;
    type Key = u32;
    type Move = u8;

    fn expand(&self, s: u32, t: &u32, wanted: impl Fn(u8) -> bool, mut visit: impl FnMut(u8, Predecessor<Self>)) {
        self.spent.set(self.spent.get() + 1);
        for a in (0..5u8).filter(|&a| wanted(a)) {
            if let Some(step) = self.predecessor(s, *t, a) {
                visit(a, step);
            }
        }
    }
    fn successors(&self, s: u32, out: &mut Vec<u32>) {
        out.extend((0..5).filter_map(|m| self.moved(s, m, 1)));
    }
    fn key(&self, _s: u32, &t: &u32) -> u32 {
        t
    }
    fn is_start(&self, s: u32, &t: &u32) -> bool {
        s == self.start && t == 0
    }
    fn start_state(&self) -> Option<u32> {
        Some(self.start)
    }
    fn heuristic(&self, s: u32, &t: &u32) -> f64 {
        // One move per step at cost ≥ 1; and at least t steps remain before reaching t.
        self.manhattan(s, self.start).max(f64::from(t))
    }
    fn exhausted(&self) -> bool {
        self.spent.get() >= self.allowed
    }
}

/// A search the domain stops ([`Domain::exhausted`]) makes no more expansions than
/// allowed, says it stopped, and — allowed more — goes on from where it stood to the
/// answer an unstopped search gives (a path, or none).
#[test]
fn a_stopped_search_says_so_and_resumes_to_the_unstopped_answer() {
    let (mut stopped_without_answer, mut stopped_with_none) = (0, 0);
    for seed in 0..60u64 {
        let mut d = TimeGrid::random(seed, 6, 5, 12, if seed % 3 == 0 { 55 } else { 25 });
        d.start = (seed % 30) as u32;
        let goal = ((seed * 7 + 13) % 30) as u32;
        let goals = || -> Vec<Goal<TimeGrid>> {
            (0..=12).filter(|&t| d.free(goal, t)).map(|t| Goal { state: goal, label: t, cost: 0.0 }).collect()
        };
        let whole = Search::new(&d, goals(), Mode::BestPathCost).plan(&d);
        let full_work = d.spent.get();
        assert!(!whole.stopped);
        if full_work < 4 {
            continue;
        }
        let mut cut = d.clone();
        cut.spent.set(0);
        cut.allowed = full_work / 2;
        let mut search = Search::new(&cut, goals(), Mode::BestPathCost);
        let first = search.plan(&cut);
        assert!(first.stopped, "seed {seed}: stopped at {} of {full_work}", cut.spent.get());
        assert_eq!(cut.spent.get(), full_work / 2, "seed {seed}: no expansion past the allowance");
        if first.path.is_none() {
            stopped_without_answer += 1;
            stopped_with_none += usize::from(whole.path.is_none());
        }
        cut.allowed = u64::MAX;
        let rest = search.plan(&cut);
        assert!(!rest.stopped);
        assert_eq!(rest.path.is_some(), whole.path.is_some(), "seed {seed}");
        if whole.path.is_some() {
            assert!((rest.cost - whole.cost).abs() < 1e-9, "seed {seed}: {} vs {}", rest.cost, whole.cost);
        }
    }
    // Stopping early is not "no path": both kinds of instance were stopped unanswered.
    assert!(stopped_without_answer > 10, "{stopped_without_answer}");
    assert!(stopped_with_none > 0 && stopped_with_none < stopped_without_answer, "{stopped_with_none}");
}

#[test]
fn time_expanded_domain_matches_brute_force() {
    let mut infeasible = 0;
    for seed in 0..60u64 {
        let mut d = TimeGrid::random(seed, 5, 4, 10, if seed % 3 == 0 { 55 } else { 25 });
        d.start = (seed % 20) as u32;
        let goal = ((seed * 7 + 13) % 20) as u32;
        let goals: Vec<Goal<TimeGrid>> =
            (0..=d.horizon).filter(|&t| d.free(goal, t)).map(|t| Goal { state: goal, label: t, cost: 0.0 }).collect();
        let plan = Search::new(&d, goals, Mode::BestPathCost).plan(&d);
        let brute = dijkstra((d.start, 0u32), |(c, t)| d.forward(c, t), |(c, _)| (c == goal).then_some(0.0));
        match (brute, &plan.path) {
            (None, None) => infeasible += 1,
            (Some(b), Some(path)) => {
                assert!((b - plan.cost).abs() < 1e-9, "seed {seed}: brute {b}, ise {}", plan.cost);
                assert_eq!(path[0].state, d.start);
                assert_eq!(path[0].label, 0);
                assert_eq!(path.last().unwrap().state, goal);
            }
            (b, p) => panic!("seed {seed}: brute {b:?}, ise found {}", p.is_some()),
        }
    }
    assert!(infeasible > 0 && infeasible < 60, "both outcomes exercised: {infeasible}");
}

/// TEMPEST's battery handling: the label carries t and the minimum energy e needed to
/// reach the goal; the backward step clamps e at 0 and abandons e > capacity.
#[derive(Debug, Clone)]
struct Battery {
    grid: TimeGrid,
    delta_e: Vec<i32>, // [t][cell]: energy used arriving at the cell at t (< 0: gained)
    capacity: i32,
    start_energy: i32,
    e_max: i32,
    duration_objective: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Charge {
    t: u32,
    e: i32,
}

impl Battery {
    fn random(seed: u64) -> Battery {
        let grid = TimeGrid::random(seed + 1000, 4, 4, 9, 15);
        let mut r = Lcg(seed * 31 + 7);
        let n = grid.cost.len();
        // Sunny cells at some times give energy; driving costs 1–3 units.
        let delta_e: Vec<i32> =
            (0..n).map(|_| if r.below(100) < 25 { -(r.below(4) as i32) - 1 } else { 1 + r.below(3) as i32 }).collect();
        let e_max = -delta_e.iter().copied().min().unwrap().min(0);
        Battery { grid, delta_e, capacity: 6, start_energy: (seed % 5) as i32, e_max, duration_objective: false }
    }
    fn step_cost(&self, de: i32) -> f64 {
        if self.duration_objective { 1.0 } else { f64::from(de + self.e_max) }
    }
    /// Forward transitions over (cell, t, battery).
    fn forward(&self, (c, t, b): (u32, u32, i32)) -> Vec<((u32, u32, i32), f64)> {
        self.grid
            .forward(c, t)
            .into_iter()
            .filter_map(|((c2, t2), _)| {
                let de = self.delta_e[self.grid.idx(c2, t2)];
                let after = (b - de).min(self.capacity);
                (b - de >= 0).then_some(((c2, t2, after), self.step_cost(de)))
            })
            .collect()
    }
}

impl Domain for Battery {
    type State = u32;
    type Label = Charge;
    type Key = (u32, i32);
    type Move = u8;
    const DOMINANCE: bool = true;

    fn expand(&self, s: u32, l: &Charge, wanted: impl Fn(u8) -> bool, mut visit: impl FnMut(u8, Predecessor<Self>)) {
        for a in (0..5u8).filter(|&a| wanted(a)) {
            if let Some(step) = self.grid.predecessor(s, l.t, a) {
                let de = self.delta_e[self.grid.idx(s, l.t)];
                let e = (l.e + de).max(0);
                visit(a, Predecessor { state: step.state, label: Charge { t: l.t - 1, e }, cost: self.step_cost(de) });
            }
        }
    }
    fn successors(&self, s: u32, out: &mut Vec<u32>) {
        self.grid.successors(s, out);
    }
    fn key(&self, _s: u32, l: &Charge) -> (u32, i32) {
        (l.t, l.e)
    }
    fn dominates(&self, _s: u32, a: &Charge, ca: f64, b: &Charge, cb: f64) -> bool {
        a.t == b.t && a.e <= b.e && ca <= cb
    }
    fn within_global(&self, _s: u32, l: &Charge, _cost: f64) -> bool {
        l.e <= self.capacity
    }
    fn is_start(&self, s: u32, l: &Charge) -> bool {
        s == self.grid.start && l.t == 0 && l.e <= self.start_energy
    }
    fn start_state(&self) -> Option<u32> {
        Some(self.grid.start)
    }
    fn heuristic(&self, s: u32, l: &Charge) -> f64 {
        if self.duration_objective { self.grid.manhattan(s, self.grid.start).max(f64::from(l.t)) } else { 0.0 }
    }
    fn better(&self, a: &Charge, b: &Charge) -> bool {
        a.e < b.e
    }
}

fn battery_goals(d: &Battery, goal: u32, goal_energy: i32, last_t: u32) -> Vec<Goal<Battery>> {
    (0..=last_t)
        .filter(|&t| d.grid.free(goal, t))
        .map(|t| Goal { state: goal, label: Charge { t, e: goal_energy }, cost: 0.0 })
        .collect()
}

#[test]
fn battery_domain_bestpcost_matches_brute_force() {
    let (mut found, mut none) = (0, 0);
    for seed in 0..80u64 {
        let mut d = Battery::random(seed);
        d.grid.start = (seed % 16) as u32;
        let goal = ((seed * 5 + 3) % 16) as u32;
        let goal_energy = (seed % 3) as i32;
        let plan = Search::new(&d, battery_goals(&d, goal, goal_energy, d.grid.horizon), Mode::BestPathCost).plan(&d);
        let start = (d.grid.start, 0u32, d.start_energy);
        let brute = dijkstra(start, |s| d.forward(s), |(c, _, b)| (c == goal && b >= goal_energy).then_some(0.0));
        match (brute, &plan.path) {
            (None, None) => none += 1,
            (Some(b), Some(path)) => {
                found += 1;
                assert!((b - plan.cost).abs() < 1e-9, "seed {seed}: brute {b}, ise {}", plan.cost);
                // Replaying the plan forward keeps the battery within [0, capacity].
                let mut battery = d.start_energy;
                for w in path.windows(2) {
                    let de = d.delta_e[d.grid.idx(w[1].state, w[1].label.t)];
                    assert!(battery - de >= 0, "seed {seed}: battery would go negative");
                    battery = (battery - de).min(d.capacity);
                }
                assert!(battery >= goal_energy);
            }
            (b, p) => panic!("seed {seed}: brute {b:?}, ise found {}", p.is_some()),
        }
    }
    assert!(found > 10 && none > 0, "found {found}, none {none}");
}

#[test]
fn battery_domain_bestdparms_finds_least_required_energy() {
    let mut checked = 0;
    for seed in 0..60u64 {
        let mut d = Battery::random(seed);
        d.duration_objective = true;
        d.start_energy = d.capacity;
        d.grid.start = (seed % 16) as u32;
        let goal = ((seed * 5 + 3) % 16) as u32;
        let max_duration = 4 + (seed % 5) as u32;
        let goals = battery_goals(&d, goal, 0, max_duration.min(d.grid.horizon));
        let plan = Search::new(&d, goals, Mode::BestDparms { max_cost: f64::from(max_duration) }).plan(&d);
        // Brute force: the least initial charge from which some path of at most
        // `max_duration` steps reaches the goal.
        let least = (0..=d.capacity).find(|&b0| {
            dijkstra(
                (d.grid.start, 0u32, b0),
                |s| if s.1 >= max_duration { vec![] } else { d.forward(s) },
                |(c, _, _)| (c == goal).then_some(0.0),
            )
            .is_some()
        });
        match (least, &plan.path) {
            (None, None) => {}
            (Some(b0), Some(path)) => {
                checked += 1;
                assert_eq!(path[0].label.e, b0, "seed {seed}");
                assert!(plan.cost <= f64::from(max_duration));
            }
            (b, p) => panic!("seed {seed}: brute {b:?}, ise found {}", p.is_some()),
        }
    }
    assert!(checked > 10, "{checked}");
}

/// The battery domain with many labels per state, dominance tested within each time
/// step only (its dominance group): the engine's group lists instead of walks over
/// every label at a cell.
#[derive(Debug, Clone)]
struct Grouped(Battery);

impl Domain for Grouped {
    type State = u32;
    type Label = Charge;
    type Key = (u32, i32);
    type Move = u8;
    const DOMINANCE: bool = true;
    const MANY_LABELS: bool = true;

    fn expand(&self, s: u32, l: &Charge, wanted: impl Fn(u8) -> bool, mut visit: impl FnMut(u8, Predecessor<Self>)) {
        self.0.expand(s, l, wanted, |a, st| visit(a, Predecessor { state: st.state, label: st.label, cost: st.cost }));
    }
    fn successors(&self, s: u32, out: &mut Vec<u32>) {
        self.0.successors(s, out);
    }
    fn key(&self, s: u32, l: &Charge) -> (u32, i32) {
        self.0.key(s, l)
    }
    fn dominance_group(&self, _s: u32, key: (u32, i32)) -> (u32, i32) {
        (key.0, 0)
    }
    fn dominates(&self, s: u32, a: &Charge, ca: f64, b: &Charge, cb: f64) -> bool {
        self.0.dominates(s, a, ca, b, cb)
    }
    fn within_global(&self, s: u32, l: &Charge, cost: f64) -> bool {
        self.0.within_global(s, l, cost)
    }
    fn is_start(&self, s: u32, l: &Charge) -> bool {
        self.0.is_start(s, l)
    }
    fn start_state(&self) -> Option<u32> {
        self.0.start_state()
    }
    fn heuristic(&self, s: u32, l: &Charge) -> f64 {
        self.0.heuristic(s, l)
    }
    fn better(&self, a: &Charge, b: &Charge) -> bool {
        self.0.better(a, b)
    }
}

fn grouped_goals(d: &Battery, goal: u32, goal_energy: i32, last_t: u32) -> Vec<Goal<Grouped>> {
    battery_goals(d, goal, goal_energy, last_t)
        .into_iter()
        .map(|g| Goal { state: g.state, label: g.label, cost: g.cost })
        .collect()
}

#[test]
fn dominance_groups_equal_brute_force_in_both_modes() {
    let (mut cost_checked, mut energy_checked) = (0, 0);
    for seed in 0..80u64 {
        let mut d = Battery::random(seed);
        d.grid.start = (seed % 16) as u32;
        let goal = ((seed * 5 + 3) % 16) as u32;
        let goal_energy = (seed % 3) as i32;
        let g = Grouped(d.clone());
        let plan = Search::new(&g, grouped_goals(&d, goal, goal_energy, d.grid.horizon), Mode::BestPathCost).plan(&g);
        let start = (d.grid.start, 0u32, d.start_energy);
        let brute = dijkstra(start, |s| d.forward(s), |(c, _, b)| (c == goal && b >= goal_energy).then_some(0.0));
        match (brute, &plan.path) {
            (None, None) => {}
            (Some(b), Some(_)) => {
                cost_checked += 1;
                assert!((b - plan.cost).abs() < 1e-9, "seed {seed}: brute {b}, grouped {}", plan.cost);
            }
            (b, p) => panic!("seed {seed}: brute {b:?}, grouped found {}", p.is_some()),
        }
        // BESTDPARMS: the least starting charge under a step cap.
        d.duration_objective = true;
        d.start_energy = d.capacity;
        let max_duration = 4 + (seed % 5) as u32;
        let g = Grouped(d.clone());
        let goals = grouped_goals(&d, goal, 0, max_duration.min(d.grid.horizon));
        let plan = Search::new(&g, goals, Mode::BestDparms { max_cost: f64::from(max_duration) }).plan(&g);
        let least = (0..=d.capacity).find(|&b0| {
            dijkstra(
                (d.grid.start, 0u32, b0),
                |s| if s.1 >= max_duration { vec![] } else { d.forward(s) },
                |(c, _, _)| (c == goal).then_some(0.0),
            )
            .is_some()
        });
        match (least, &plan.path) {
            (None, None) => {}
            (Some(b0), Some(path)) => {
                energy_checked += 1;
                assert_eq!(path[0].label.e, b0, "seed {seed}");
            }
            (b, p) => panic!("seed {seed}: brute {b:?}, grouped found {}", p.is_some()),
        }
    }
    assert!(cost_checked > 10 && energy_checked > 10, "{cost_checked} {energy_checked}");
}

#[test]
fn replaced_goals_repair_to_the_fresh_answer() {
    // set_goals keeps the goals that stay and removes the others with their subtrees:
    // the repaired graph answers as a search from the new goals alone.
    let mut checked = 0;
    for seed in 0..60u64 {
        let mut d = Battery::random(seed);
        d.grid.start = (seed % 16) as u32;
        d.start_energy = d.capacity;
        let goal = ((seed * 5 + 3) % 16) as u32;
        let g = Grouped(d.clone());
        let all = grouped_goals(&d, goal, 0, d.grid.horizon);
        let mut search = Search::new(&g, all.clone(), Mode::BestPathCost);
        search.plan(&g);
        // Keep every other goal, change the cost of a third, add one at another cell.
        let other = (goal + 7) % 16;
        let mut next: Vec<Goal<Grouped>> = all
            .iter()
            .enumerate()
            .filter(|(i, _)| i % 2 == 0)
            .map(|(i, g)| Goal { state: g.state, label: g.label, cost: if i % 3 == 0 { 1.5 } else { 0.0 } })
            .collect();
        next.extend(grouped_goals(&d, other, 1, d.grid.horizon / 2));
        search.set_goals(&g, next.clone());
        let repaired = search.plan(&g);
        let fresh = Search::new(&g, next, Mode::BestPathCost).plan(&g);
        assert_eq!(repaired.path.is_some(), fresh.path.is_some(), "seed {seed}");
        if fresh.path.is_some() {
            checked += 1;
            assert!((repaired.cost - fresh.cost).abs() < 1e-9, "seed {seed}: {} vs {}", repaired.cost, fresh.cost);
        }
    }
    assert!(checked > 10, "{checked}");
}
