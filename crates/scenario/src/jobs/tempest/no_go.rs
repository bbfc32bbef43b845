//! The no-go mask: the cells a raster marks (non-zero) kept out of, found for each cell
//! of the map by nearest neighbour (the cell of the mask under the map cell's centre),
//! grown by a disc of `inflate_m`, and the ground those cells cut off from the start
//! kept out too — a goal there is an error, never a plan into an island.
//!
//! A mask with a CRS must be on the map's, in its projected metres. One without (an
//! ESRI ASCII grid) is in the scenario's metres — east and north of the map's
//! south-west corner, as `start` and `goals` are — unless the map has no CRS either,
//! when the two share the map file's numbers.

use std::collections::VecDeque;

use super::overlay;
use super::*;
use crate::format::NoGoSpec;
use crate::report::tempest::NoGoFigures;

/// What keeps a cell out, as the `no_go.tif` layer writes it.
pub(super) const FREE: u8 = 0;
/// Marked by the mask.
pub(super) const MASKED: u8 = 1;
/// Within `inflate_m` of a masked cell.
pub(super) const INFLATED: u8 = 2;
/// Cut off from the start by the mask (and missing data).
pub(super) const ISLAND: u8 = 3;

/// The start and the goal cells.
pub(super) type Placed = (Start, Vec<u32>);

/// The mask applied: what keeps each cell of the map out, and its figures.
#[derive(Debug, Clone)]
pub(super) struct NoGo {
    /// Per map cell: [`FREE`], [`MASKED`], [`INFLATED`] or [`ISLAND`].
    pub codes: Vec<u8>,
    pub figures: NoGoFigures,
}

/// Reads the job's mask onto `world`'s grid and inflates it; blocks those cells in
/// `world` (and `truth`). The start and goals (`places`: field and map metres) must lie
/// outside it. Islands are found by [`cut_off`] once the start is known.
pub(super) fn apply(
    spec: &NoGoSpec,
    file: &ScenarioFile,
    worlds: (&World, Option<&World>),
    frame: Frame,
    places: &[(String, (f64, f64))],
) -> Result<NoGo> {
    let world = worlds.0;
    let mut codes = marked(spec, file, world, frame)?;
    let masked = codes.iter().filter(|&&c| c == MASKED).count();
    inflate(world, &mut codes, spec.inflate_m);
    let inflated = codes.iter().filter(|&&c| c == INFLATED).count();
    for (what, (x, y)) in places {
        if let Some(cell) = world.cell_at(*x, *y)
            && codes[cell as usize] != FREE
        {
            let why =
                if codes[cell as usize] == MASKED { "in the no-go mask" } else { "within inflate_m of the no-go mask" };
            // Said in the scenario's own metres (as written), the map's beside them.
            let (sx, sy) = frame.to_local((*x, *y));
            return Err(scenario_error(
                file,
                what.clone(),
                format!(
                    "({sx:.1}, {sy:.1}) m (the map's ({x:.1}, {y:.1}) m) is {why} ({}, inflated by {} m): move it or \
                     the mask",
                    spec.file, spec.inflate_m
                ),
            ));
        }
    }
    block(worlds, &codes);
    Ok(NoGo {
        codes,
        figures: NoGoFigures {
            file: spec.file.clone(),
            inflate_m: spec.inflate_m,
            masked_cells: masked,
            inflated_cells: inflated,
            island_cells: 0,
            kept_out_fraction: (masked + inflated) as f64 / world.cells() as f64,
            prepare_s: 0.0,
        },
    })
}

/// The job's mask read onto `world`'s grid: [`MASKED`] where the mask cell under a map
/// cell's centre is non-zero, else [`FREE`].
fn marked(spec: &NoGoSpec, file: &ScenarioFile, world: &World, frame: Frame) -> Result<Vec<u8>> {
    let field = "job.no_go.file";
    let samples = overlay::sample(&spec.file, field, file, world, frame)?;
    let unknown = samples.iter().filter(|s| matches!(s, overlay::Sample::NoData)).count();
    if unknown > 0 {
        return Err(scenario_error(
            file,
            field.to_string(),
            format!(
                "{}: {unknown} cells of the map fall on cells of the mask with no value (NaN or its no-data): a mask gives every cell it covers 0 (free) or non-zero (keep out)",
                spec.file
            ),
        ));
    }
    Ok(samples
        .iter()
        .map(|s| if matches!(s, overlay::Sample::Value(v) if *v != 0.0) { MASKED } else { FREE })
        .collect())
}

/// Blocks every cell `codes` keeps out in the worlds.
fn block((world, truth): (&World, Option<&World>), codes: &[u8]) {
    let cells: Vec<u32> = (0..codes.len() as u32).filter(|&c| codes[c as usize] != FREE).collect();
    world.set_blocked(&cells, true);
    if let Some(t) = truth {
        t.set_blocked(&cells, true);
    }
}

/// Marks [`INFLATED`] every free cell whose centre lies within `radius_m` of a masked
/// cell's centre. The squared distance from every cell to the nearest masked one is an
/// exact Euclidean distance transform, separable in columns and rows (Felzenszwalb &
/// Huttenlocher's lower envelope of parabolas, with the map's own dx and dy): one f64
/// a cell and a few passes whatever the radius — a disc of cells per masked cell would
/// grow with the radius squared (a 10 km disc on 1 m cells is 3 × 10⁸ offsets).
fn inflate(world: &World, codes: &mut [u8], radius_m: f64) {
    if radius_m <= 0.0 {
        return;
    }
    let (cols, rows) = (world.cols(), world.rows());
    let (dx, dy) = (world.dem().dx(), world.dem().dy());
    let mut d2: Vec<f64> = codes.iter().map(|&c| if c == MASKED { 0.0 } else { f64::INFINITY }).collect();
    let mut line = Vec::new();
    let mut envelope = Envelope::default();
    for r in 0..rows {
        line.clear();
        line.extend_from_slice(&d2[r * cols..(r + 1) * cols]);
        envelope.transform(&line, dx * dx, &mut d2[r * cols..(r + 1) * cols]);
    }
    let mut out = vec![0.0; rows];
    for c in 0..cols {
        line.clear();
        line.extend((0..rows).map(|r| d2[r * cols + c]));
        envelope.transform(&line, dy * dy, &mut out);
        for (r, v) in out.iter().enumerate() {
            d2[r * cols + c] = *v;
        }
    }
    for (code, d) in codes.iter_mut().zip(&d2) {
        if *code == FREE && d.sqrt() <= radius_m {
            *code = INFLATED;
        }
    }
}

/// The 1-D squared distance transform: `out[q]` = min over p of `w`·(q − p)² + `f[p]`,
/// by the lower envelope of the parabolas rooted at the finite `f[p]`.
#[derive(Default)]
struct Envelope {
    /// The parabolas' roots, in order.
    roots: Vec<usize>,
    /// Where each parabola starts to be the lowest (`starts[k]` for `roots[k]`).
    starts: Vec<f64>,
}

impl Envelope {
    fn transform(&mut self, f: &[f64], w: f64, out: &mut [f64]) {
        self.roots.clear();
        self.starts.clear();
        // Where the parabolas of p and q (p < q) cross.
        let cross = |p: usize, q: usize| {
            let (p, q) = (p as f64, q as f64);
            ((f[q as usize] / w + q * q) - (f[p as usize] / w + p * p)) / (2.0 * (q - p))
        };
        for q in (0..f.len()).filter(|&q| f[q].is_finite()) {
            loop {
                match self.roots.last() {
                    Some(&p) if cross(p, q) <= *self.starts.last().expect("one start per root") => {
                        self.roots.pop();
                        self.starts.pop();
                    }
                    Some(&p) => {
                        self.starts.push(cross(p, q));
                        break;
                    }
                    None => {
                        self.starts.push(f64::NEG_INFINITY);
                        break;
                    }
                }
            }
            self.roots.push(q);
        }
        if self.roots.is_empty() {
            out.fill(f64::INFINITY);
            return;
        }
        let mut k = 0;
        for (q, o) in out.iter_mut().enumerate() {
            while k + 1 < self.roots.len() && self.starts[k + 1] < q as f64 {
                k += 1;
            }
            let p = self.roots[k];
            let d = q as f64 - p as f64;
            *o = w * d * d + f[p];
        }
    }
}

/// Marks [`ISLAND`] (and blocks) every passable cell the start cannot reach by 8-connected
/// steps over passable cells; a goal among them is an error naming it.
pub(super) fn cut_off(
    no_go: &mut NoGo,
    file: &ScenarioFile,
    worlds: (&World, Option<&World>),
    start: u32,
    goals: &[(String, u32)],
) -> Result<()> {
    let world = worlds.0;
    let (cols, rows) = (world.cols() as i64, world.rows() as i64);
    let mut reached = vec![false; world.cells()];
    let mut queue = VecDeque::from([start]);
    reached[start as usize] = true;
    while let Some(cell) = queue.pop_front() {
        let (c0, r0) = world.col_row(cell);
        for (dc, dr) in [(-1, -1), (0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (0, 1), (1, 1)] {
            let (c, r) = (c0 as i64 + dc, r0 as i64 + dr);
            if c < 0 || r < 0 || c >= cols || r >= rows {
                continue;
            }
            let next = world.cell(c as usize, r as usize);
            if !reached[next as usize] && world.passable(next) {
                reached[next as usize] = true;
                queue.push_back(next);
            }
        }
    }
    let island: Vec<u32> = (0..world.cells() as u32).filter(|&c| !reached[c as usize] && world.passable(c)).collect();
    for (field, goal) in goals {
        if !reached[*goal as usize] {
            return Err(scenario_error(
                file,
                field.clone(),
                format!(
                    "cut off from the start by the no-go mask ({}) and missing data: an island of {} cells the rover cannot reach",
                    no_go.figures.file,
                    island.len()
                ),
            ));
        }
    }
    for &c in &island {
        no_go.codes[c as usize] = ISLAND;
    }
    no_go.figures.island_cells = island.len();
    worlds.0.set_blocked(&island, true);
    if let Some(t) = worlds.1 {
        t.set_blocked(&island, true);
    }
    Ok(())
}

/// The job's no-go mask applied to the worlds (with the islands it cuts off from the
/// start), timed, and the start and goal cells.
pub(super) fn on(
    job: &TempestJob,
    file: &ScenarioFile,
    worlds: (&World, Option<&World>),
    frame: Frame,
) -> Result<(Option<NoGo>, Placed)> {
    let goal_fields: Vec<String> = (0..job.goals.len()).map(|i| format!("job.goals[{i}]")).collect();
    let clock = Instant::now();
    let mut no_go = match &job.no_go {
        Some(spec) => {
            let places: Vec<(String, (f64, f64))> =
                std::iter::once(("job.start".to_string(), (job.start.x_m, job.start.y_m)))
                    .chain(goal_fields.iter().cloned().zip(job.goals.iter().map(|g| (g.x_m, g.y_m))))
                    .map(|(field, (x, y))| (field, frame.to_map(x, y)))
                    .collect();
            Some(apply(spec, file, worlds, frame, &places)?)
        }
        None => None,
    };
    let (start, goals) = locate(job, file, worlds.0, frame)?;
    if let Some(n) = &mut no_go {
        let named: Vec<(String, u32)> = goal_fields.into_iter().zip(goals.iter().copied()).collect();
        cut_off(n, file, worlds, start.cell, &named)?;
        n.figures.prepare_s = clock.elapsed().as_secs_f64();
    }
    Ok((no_go, (start, goals)))
}

#[cfg(test)]
mod tests {
    use super::Envelope;
    use rand::{RngExt, SeedableRng};

    /// The transform equals the brute force min over every masked cell of the squared
    /// distance, with unequal dx and dy, on seeded random masks.
    #[test]
    fn the_distance_transform_is_the_brute_force_on_random_masks() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        for case in 0..200 {
            let (cols, rows) = (rng.random_range(1..30), rng.random_range(1..30));
            let (dx, dy) = (rng.random_range(0.3..5.0), rng.random_range(0.3..5.0));
            let density = [0.0, 0.01, 0.1, 0.5, 1.0][case % 5];
            let masked: Vec<bool> = (0..cols * rows).map(|_| rng.random_bool(density)).collect();
            let mut d2: Vec<f64> = masked.iter().map(|&m| if m { 0.0 } else { f64::INFINITY }).collect();
            let mut env = Envelope::default();
            let mut out = vec![0.0; cols.max(rows)];
            for r in 0..rows {
                let line = d2[r * cols..(r + 1) * cols].to_vec();
                env.transform(&line, dx * dx, &mut out[..cols]);
                d2[r * cols..(r + 1) * cols].copy_from_slice(&out[..cols]);
            }
            for c in 0..cols {
                let line: Vec<f64> = (0..rows).map(|r| d2[r * cols + c]).collect();
                env.transform(&line, dy * dy, &mut out[..rows]);
                for r in 0..rows {
                    d2[r * cols + c] = out[r];
                }
            }
            for (i, &got) in d2.iter().enumerate() {
                let (c, r) = ((i % cols) as f64, (i / cols) as f64);
                let brute = (0..cols * rows)
                    .filter(|&j| masked[j])
                    .map(|j| ((c - (j % cols) as f64) * dx).powi(2) + ((r - (j / cols) as f64) * dy).powi(2))
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    (got - brute).abs() <= 1e-9 * brute.max(1.0) || (got.is_infinite() && brute.is_infinite()),
                    "case {case}, cell {i}: {got} vs {brute}"
                );
            }
        }
    }
}
