//! `areo grid`: one line per Moving AI scenario, then `N solved, M mismatched`.

use areo_scenario::Error;
use areo_scenario::grid::GridRow;

use crate::Format;

/// The rows in the chosen format; `replan` adds the re-planning columns.
pub(crate) fn rows(rows: &[GridRow], replan: bool, format: Format) -> Result<String, Error> {
    if format == Format::Json {
        return Ok(super::json(&rows)? + "\n");
    }
    let mut s = String::new();
    match format {
        Format::Csv | Format::Json => {
            let extra = if replan { ",replanned,fresh,replan_expansions" } else { "" };
            s += &format!("index,expected,found,expansions{extra}\n");
        }
        Format::Text => {
            let extra = if replan {
                format!(" {:>14} {:>14} {:>10}", "replanned", "fresh", "repair exp")
            } else {
                String::new()
            };
            s += &format!("{:>6} {:>14} {:>14} {:>10}{extra}\n", "index", "expected", "found", "expansions");
        }
    }
    for r in rows {
        let replan = r.replanned.zip(r.fresh).zip(r.replan_expansions).map(|((a, b), e)| (a, b, e));
        let extra = match (replan, format) {
            (Some((a, b, e)), Format::Text) => format!(" {a:>14.6} {b:>14.6} {e:>10}"),
            (Some((a, b, e)), _) => format!(",{a:.8},{b:.8},{e}"),
            (None, _) => String::new(),
        };
        s += &match format {
            Format::Text => {
                format!("{:>6} {:>14.6} {:>14.6} {:>10}{extra}\n", r.index, r.expected, r.found, r.expansions)
            }
            _ => format!("{},{},{:.8},{}{extra}\n", r.index, r.expected, r.found, r.expansions),
        };
    }
    let mismatched = rows.iter().filter(|r| r.mismatched).count();
    let solved = rows.len() - rows.iter().filter(|r| r.found.is_infinite()).count();
    s += &format!("{solved} solved, {mismatched} mismatched\n");
    Ok(s)
}
