//! The Incremental Search Engine on an 8-connected grid (Moving AI rules): a path round
//! a wall, then re-planned when a gap opens — `cargo run -p areo-ise --example grid_search`.

#![allow(clippy::print_stdout)] // an example prints what it shows

use areo_ise::grid::Grid;
use areo_ise::{Goal, Mode, Search};

fn main() {
    let map = "type octile\nheight 7\nwidth 9\nmap\n\
               .........\n\
               .........\n\
               ....@....\n\
               ....@....\n\
               ....@....\n\
               .........\n\
               .........\n";
    let mut grid = Grid::parse_movingai(map).expect("a valid map");
    grid.set_start(grid.cell(0, 3));
    let goal = Goal { state: grid.cell(8, 3), label: (), cost: 0.0 };
    let mut search = Search::new(&grid, [goal], Mode::BestPathCost);
    let first = search.plan(&grid);
    println!("round the wall: cost {:.3} ({} expansions)", first.cost, first.stats.expansions);
    // A gap opens in the wall: tell the search which states changed and re-plan.
    let gap = grid.cell(4, 3);
    grid.set_free(gap, true);
    search.update(&grid, &grid.changed_states(gap, true));
    let second = search.plan(&grid);
    println!("through the gap: cost {:.3} ({} expansions)", second.cost, second.stats.expansions);
    assert!(second.cost < first.cost);
}
