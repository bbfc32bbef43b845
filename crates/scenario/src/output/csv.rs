//! CSV tables through the `csv` crate: every field is quoted as RFC 4180 needs, so a
//! user's goal or sample name with a comma, quote or newline cannot shift a column.

use std::borrow::Cow;
use std::path::Path;

use serde::Serialize;

use crate::error::{Error, Result};

/// A number written with `N` decimals in a CSV row (the column's precision, chosen by
/// the row type).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct Fixed<const N: usize>(pub(crate) f64);

impl<const N: usize> Serialize for Fixed<N> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        let text = format!("{:.*}", N, self.0);
        // A value that rounds to zero is written without a sign: "-0.00" would read as
        // a negative in a spreadsheet and in a diff.
        match text.strip_prefix('-') {
            Some(unsigned) if unsigned.bytes().all(|b| b == b'0' || b == b'.') => s.collect_str(unsigned),
            _ => s.collect_str(&text),
        }
    }
}

/// Rows of a serialisable row type as CSV text: the header is the type's field names
/// (written even when there are no rows), each row its fields in order (`None` an empty
/// field). `path` names the file in errors.
pub(crate) fn rows_to_csv<R: Serialize + Default>(path: &Path, rows: impl IntoIterator<Item = R>) -> Result<String> {
    let fail = |e: csv::Error| Error::Io { path: path.to_path_buf(), source: std::io::Error::other(e) };
    let mut header = csv::WriterBuilder::new().from_writer(Vec::new());
    header.serialize(R::default()).map_err(fail)?;
    let bytes = header.into_inner().map_err(|e| Error::Io { path: path.to_path_buf(), source: e.into_error() })?;
    let names = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(bytes.as_slice())
        .records()
        .next()
        .transpose()
        .map_err(fail)?
        .unwrap_or_default();
    let mut w =
        csv::WriterBuilder::new().has_headers(false).terminator(csv::Terminator::Any(b'\n')).from_writer(Vec::new());
    w.write_record(&names).map_err(fail)?;
    for row in rows {
        w.serialize(row).map_err(fail)?;
    }
    let bytes = w.into_inner().map_err(|e| Error::Io { path: path.to_path_buf(), source: e.into_error() })?;
    let text = String::from_utf8(bytes)
        .map_err(|e| Error::Io { path: path.to_path_buf(), source: std::io::Error::other(e) })?;
    defuse(path, text)
}

/// CSV text with every cell passed through [`super::escape::csv_cell`] (read back and
/// written again only where a cell needs it).
fn defuse(path: &Path, text: String) -> Result<String> {
    let fail = |e: csv::Error| Error::Io { path: path.to_path_buf(), source: std::io::Error::other(e) };
    let records: Vec<csv::StringRecord> = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(text.as_bytes())
        .records()
        .collect::<std::result::Result<_, _>>()
        .map_err(fail)?;
    let needs = |r: &csv::StringRecord| r.iter().any(|f| matches!(super::escape::csv_cell(f), Cow::Owned(_)));
    if !records.iter().any(needs) {
        return Ok(text);
    }
    let mut w =
        csv::WriterBuilder::new().has_headers(false).terminator(csv::Terminator::Any(b'\n')).from_writer(Vec::new());
    for r in &records {
        w.write_record(r.iter().map(super::escape::csv_cell).collect::<Vec<_>>().iter().map(|c| c.as_bytes()))
            .map_err(fail)?;
    }
    let bytes = w.into_inner().map_err(|e| Error::Io { path: path.to_path_buf(), source: e.into_error() })?;
    String::from_utf8(bytes).map_err(|e| Error::Io { path: path.to_path_buf(), source: std::io::Error::other(e) })
}

/// Writes [`rows_to_csv`] to `path` atomically.
pub(crate) fn write_rows<R: Serialize + Default>(path: &Path, rows: impl IntoIterator<Item = R>) -> Result<()> {
    super::write_file(path, rows_to_csv(path, rows)?.as_bytes())
}

/// A CSV table built in memory: a header and rows of already formatted fields (the
/// caller chooses each column's decimals).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Table {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    /// A table with these column names.
    pub fn new<S: Into<String>>(header: impl IntoIterator<Item = S>) -> Table {
        Table { header: header.into_iter().map(Into::into).collect(), rows: Vec::new() }
    }

    /// Appends a row. Its length must match the header's (a programming error
    /// otherwise, caught by the writer).
    pub fn push(&mut self, row: Vec<String>) {
        self.rows.push(row);
    }

    /// The number of data rows.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// Whether the table has no data rows.
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// The table as CSV text; `path` names the file in the error if a row's width
    /// differs from the header's.
    pub fn to_csv(&self, path: &Path) -> Result<String> {
        let fail = |e: csv::Error| Error::Io { path: path.to_path_buf(), source: std::io::Error::other(e) };
        let mut w = csv::WriterBuilder::new().terminator(csv::Terminator::Any(b'\n')).from_writer(Vec::new());
        w.write_record(&self.header).map_err(fail)?;
        for row in &self.rows {
            w.write_record(row.iter().map(|c| super::escape::csv_cell(c).into_owned())).map_err(fail)?;
        }
        let bytes = w.into_inner().map_err(|e| Error::Io { path: path.to_path_buf(), source: e.into_error() })?;
        String::from_utf8(bytes).map_err(|e| Error::Io { path: path.to_path_buf(), source: std::io::Error::other(e) })
    }

    /// Writes the table to `path` atomically (a `.partial` file renamed into place).
    pub fn write(&self, path: &Path) -> Result<()> {
        super::write_file(path, self.to_csv(path)?.as_bytes())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_with_commas_quotes_and_newlines_keep_their_column() {
        let mut t = Table::new(["goal", "x_m"]);
        t.push(vec!["crater rim, north".into(), "1.5".into()]);
        t.push(vec!["the \"saddle\"\nnorth".into(), "2".into()]);
        let text = t.to_csv(Path::new("plan.csv")).unwrap();
        assert_eq!(text, "goal,x_m\n\"crater rim, north\",1.5\n\"the \"\"saddle\"\"\nnorth\",2\n");
        // Read back with the same crate: every row has two fields, names intact.
        let mut r = csv::Reader::from_reader(text.as_bytes());
        let rows: Vec<csv::StringRecord> = r.records().map(|x| x.unwrap()).collect();
        assert_eq!(rows.len(), 2);
        assert_eq!(&rows[0][0], "crater rim, north");
        assert_eq!(&rows[1][0], "the \"saddle\"\nnorth");
    }

    #[test]
    fn serialised_rows_keep_their_decimals_header_and_empty_fields() {
        #[derive(Serialize, Default)]
        struct Row {
            name: String,
            x_m: Fixed<2>,
            lit: u8,
            fresh_cost: Option<Fixed<4>>,
        }
        let rows = [
            Row { name: "rim, north".into(), x_m: Fixed(1.005), lit: 1, fresh_cost: None },
            Row { name: "saddle".into(), x_m: Fixed(-2.0), lit: 0, fresh_cost: Some(Fixed(3314.2)) },
        ];
        let text = rows_to_csv(Path::new("t.csv"), rows).unwrap();
        assert_eq!(text, "name,x_m,lit,fresh_cost\n\"rim, north\",1.00,1,\nsaddle,-2.00,0,3314.2000\n");
        // No rows: the header alone.
        assert_eq!(rows_to_csv(Path::new("t.csv"), Vec::<Row>::new()).unwrap(), "name,x_m,lit,fresh_cost\n");
    }

    #[test]
    fn a_row_of_the_wrong_width_is_an_error_naming_the_file() {
        let mut t = Table::new(["a", "b"]);
        t.push(vec!["1".into()]);
        let err = t.to_csv(Path::new("out/x/plan.csv")).unwrap_err();
        assert!(err.to_string().contains("out/x/plan.csv"), "{err}");
    }

    #[test]
    fn values_that_round_to_zero_have_no_sign() {
        #[derive(Serialize, Default)]
        struct Row {
            a: Fixed<2>,
            b: Fixed<2>,
            c: Fixed<0>,
        }
        let rows = [
            Row { a: Fixed(-1e-15), b: Fixed(-0.004), c: Fixed(-0.4) },
            Row { a: Fixed(-0.005001), b: Fixed(-2.5), c: Fixed(-0.0) },
        ];
        let text = rows_to_csv(Path::new("t.csv"), rows).unwrap();
        assert_eq!(text, "a,b,c\n0.00,0.00,0\n-0.01,-2.50,0\n");
    }
}
