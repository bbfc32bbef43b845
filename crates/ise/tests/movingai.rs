//! ISE's path cost equals the published optimal length of every scenario of six Moving
//! AI maps of five kinds.

use std::path::PathBuf;

use areo_ise::grid::{Grid, parse_scenarios};
use areo_ise::{Goal, Mode, Search};

fn data(name: &str) -> String {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/movingai").join(name);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Tolerance for a published length: 1e-6 for 8-decimal files, one unit of the 6th
/// significant digit for the legacy files (they truncate: 235.7645… is printed 235.764).
fn tolerance(expected: f64, printed: &str) -> f64 {
    match printed.split_once('.') {
        Some((_, frac)) if frac.trim().len() >= 8 => 1e-6,
        _ => 10f64.powi(expected.abs().log10().floor() as i32 - 5) + 1e-9,
    }
}

fn check_map(map: &str) {
    let mut grid = Grid::parse_movingai(&data(map)).unwrap();
    let scen_text = data(&format!("{map}.scen"));
    let scenarios = parse_scenarios(&scen_text).unwrap();
    let printed: Vec<&str> =
        scen_text.lines().skip(1).filter(|l| !l.trim().is_empty()).map(|l| l.rsplit('\t').next().unwrap()).collect();
    assert_eq!(printed.len(), scenarios.len());
    let mut mismatches = Vec::new();
    for (i, s) in scenarios.iter().enumerate() {
        grid.set_start(grid.cell(s.start_x, s.start_y));
        let goal = Goal { state: grid.cell(s.goal_x, s.goal_y), label: (), cost: 0.0 };
        let plan = Search::new(&grid, [goal], Mode::BestPathCost).plan(&grid);
        let tol = tolerance(s.optimal, printed[i]);
        if (plan.cost - s.optimal).abs() > tol {
            mismatches.push((i, s.optimal, plan.cost));
        }
        // The path is a real path of that cost.
        let path = plan.path.expect("every benchmark scenario is solvable");
        let mut walked = 0.0;
        for w in path.windows(2) {
            let step =
                grid.neighbours(w[0].state).find(|(b, _)| *b == w[1].state).expect("consecutive cells are neighbours");
            walked += step.1;
        }
        assert!((walked - plan.cost).abs() < 1e-9);
    }
    assert!(
        mismatches.is_empty(),
        "{map}: {} mismatches, first {:?}",
        mismatches.len(),
        &mismatches[..mismatches.len().min(5)]
    );
}

#[test]
fn dao_arena() {
    check_map("arena.map");
}

#[test]
fn dao_den520d() {
    check_map("den520d.map");
}

#[test]
fn street_berlin_256() {
    check_map("Berlin_0_256.map");
}

#[test]
fn random_512_10() {
    check_map("random512-10-0.map");
}

#[test]
fn rooms_8room_512() {
    check_map("8room_000.map");
}

#[test]
fn baldurs_gate_ar0011sr() {
    check_map("AR0011SR.map");
}

#[test]
fn malformed_maps_are_errors() {
    assert!(Grid::parse_movingai("type octile\nheight 2\nwidth 3\nmap\n...\n..\n").is_err());
    assert!(Grid::parse_movingai("type octile\nheight 2\nwidth 3\nmap\n...\n").is_err());
    assert!(Grid::parse_movingai("height x\nwidth 3\nmap\n").is_err());
    assert!(Grid::parse_movingai("").is_err());
    // Only octile maps are solved; a hexagonal one is refused, not solved as octile.
    let err = Grid::parse_movingai("type hex\nheight 1\nwidth 3\nmap\n...\n").unwrap_err().to_string();
    assert!(err.contains("line 1") && err.contains("octile"), "{err}");
    // A header declaring 1.6e9 cells in a 40-byte file is refused before allocating.
    let err = Grid::parse_movingai("type octile\nheight 40000\nwidth 40000\nmap\n").unwrap_err().to_string();
    assert!(err.contains("40000x40000") && err.contains("bytes"), "{err}");
    assert!(parse_scenarios("version 1\n0\tm\t1\t1\t0\t0\n").is_err());
}

/// The grid's one-at-a-time `visit_predecessors` (what the engine expands with) gives
/// exactly the steps of `predecessors` (the per-move definition), in the same order,
/// at every cell of a real map with uneven weights.
#[test]
fn grid_expands_to_the_moves_it_allows_whatever_else_is_wanted() {
    use areo_ise::Domain;
    let mut grid = Grid::parse_movingai(&data("den520d.map")).unwrap();
    let cells: Vec<u32> = grid.cells().collect();
    for (k, &c) in cells.iter().enumerate() {
        grid.set_weight(c, 1.0 + (k % 7) as f32 * 0.25);
    }
    let mut steps_seen = 0;
    for &c in &cells {
        let mut all = Vec::new();
        grid.expand(c, &(), |_| true, |a, s| all.push((a, s.state, s.cost)));
        // Asking for one move at a time gives the same steps (a partial expansion
        // sees what a full one does).
        let one_by_one: Vec<(u8, u32, f64)> = (0..8u8)
            .flat_map(|want| {
                let mut v = Vec::new();
                grid.expand(c, &(), |a| a == want, |a, s| v.push((a, s.state, s.cost)));
                v
            })
            .collect();
        assert_eq!(one_by_one, all, "cell {c}");
        // Every step comes from a neighbour one move away, at a move's cost.
        for &(_, from, cost) in &all {
            let mut next = Vec::new();
            grid.successors(from, &mut next);
            assert!(from != c && next.contains(&c), "cell {c} from {from}");
            assert!(cost >= 1.0, "{cost}");
        }
        steps_seen += all.len();
    }
    assert!(steps_seen > cells.len(), "the map has open ground: {steps_seen} steps");
}
