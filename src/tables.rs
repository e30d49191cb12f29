//! Every CSV sediment reads or writes, through the csv crate: one reader for numeric
//! tables (timelines, base profiles) that takes what spreadsheets save (a UTF-8 BOM,
//! quoted cells, CRLF, a header line) and refuses what it cannot read with the line
//! and the reason; one writer whose headers carry units and which refuses a
//! non-finite number (issue 17: no NaN or inf in any output).

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result, echo};

/// One data row of a numeric table and the line it came from (1-based, as an editor
/// counts).
#[derive(Clone, Debug, PartialEq)]
pub struct NumberRow {
    /// The row's line in the input, 1-based, for messages.
    pub line: u64,
    /// The row's finite numbers, one per column asked for, in column order.
    pub values: Vec<f64>,
}

/// Reads CSV `text` as rows of exactly `columns.len()` finite numbers. Lines starting
/// with `#` and blank lines are skipped, and so is one header line before the data (a
/// row that is not all numbers). `what` names the input in messages (`--base`,
/// `timeline`); `columns` name the values ("year", "temperature C", ...).
pub fn read_numbers(text: &str, what: &str, columns: &[&str]) -> Result<Vec<NumberRow>> {
    // Excel's "CSV UTF-8" starts with a byte order mark: it is not part of the first
    // cell (kept, it would make the first row a header, and lose it).
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    let mut rows = Vec::new();
    let mut header_seen = false;
    for record in reader.records() {
        let record =
            record.map_err(|e| Error::invalid(what, format!("not readable as CSV: {e}")))?;
        let line = record.position().map_or(0, csv::Position::line);
        if record.iter().all(str::is_empty) {
            continue;
        }
        let shown = || echo(&record.iter().collect::<Vec<_>>().join(","));
        if record.len() == 1 && columns.len() > 1 && record[0].contains(';') {
            return Err(Error::invalid(
                what,
                format!(
                    "line {line}: \"{}\" has its cells separated by ';' (a spreadsheet saving \
                     in a locale with decimal commas); sediment reads ',' between cells and '.' \
                     in numbers: save as CSV with a comma separator",
                    echo(&record[0])
                ),
            ));
        }
        let parsed: Option<Vec<f64>> = record.iter().map(|c| c.parse().ok()).collect();
        let Some(values) = parsed else {
            if rows.is_empty() && !header_seen {
                header_seen = true;
                continue;
            }
            return Err(Error::invalid(
                what,
                format!(
                    "line {line}: \"{}\" is not {} numbers ({})",
                    shown(),
                    columns.len(),
                    columns.join(", ")
                ),
            ));
        };
        if values.len() != columns.len() {
            return Err(Error::invalid(
                what,
                format!(
                    "line {line}: expected {}; found {} values",
                    columns.join(", "),
                    values.len()
                ),
            ));
        }
        if let Some((name, v)) = columns.iter().zip(&values).find(|(_, v)| !v.is_finite()) {
            return Err(Error::invalid(
                what,
                format!("line {line}: the {name} {v} is not a finite number"),
            ));
        }
        rows.push(NumberRow { line, values });
    }
    Ok(rows)
}

/// One cell of a row being written.
#[derive(Clone, Copy, Debug)]
pub enum Cell<'a> {
    /// A whole number, written in decimal.
    Int(u64),
    /// Shortest text that reads back to the same `f64`.
    Num(f64),
    /// A number with this many decimals.
    Fixed(f64, usize),
    /// Text as it is, quoted by the csv crate where it holds a comma or a quote.
    Text(&'a str),
}

/// A CSV table written row by row (so a table of millions of rows is never held),
/// with a header of units and a guard against non-finite numbers.
pub struct TableWriter<W: Write> {
    csv: csv::Writer<W>,
    what: String,
    path: PathBuf,
    columns: Vec<String>,
    rows: u64,
}

impl<W: Write> TableWriter<W> {
    /// A table of `what` (for messages) into `out` (named `path` in errors) with
    /// `header`: each column with its unit (`height_m`, `time_years`).
    pub fn new(out: W, what: &str, path: &Path, header: &[&str]) -> Result<Self> {
        let mut table = Self {
            csv: csv::Writer::from_writer(out),
            what: what.to_owned(),
            path: path.to_path_buf(),
            columns: header.iter().map(|&h| h.to_owned()).collect(),
            rows: 0,
        };
        table
            .csv
            .write_record(header)
            .map_err(|e| table.csv_error(e))?;
        Ok(table)
    }

    fn csv_error(&self, e: csv::Error) -> Error {
        let source = match e.into_kind() {
            csv::ErrorKind::Io(io) => io,
            other => std::io::Error::other(format!("{other:?}")),
        };
        Error::Write {
            path: self.path.clone(),
            source,
        }
    }

    /// Writes one row; refuses one with a non-finite number, naming its column.
    pub fn row(&mut self, cells: &[Cell<'_>]) -> Result<()> {
        self.rows += 1;
        if cells.len() != self.columns.len() {
            return Err(Error::internal(
                "CSV table",
                format!("{} cells for {} columns", cells.len(), self.columns.len()),
            ));
        }
        let mut record = csv::StringRecord::with_capacity(64, cells.len());
        for (cell, column) in cells.iter().zip(&self.columns) {
            match *cell {
                Cell::Num(v) | Cell::Fixed(v, _) if !v.is_finite() => {
                    return Err(Error::invalid(
                        self.what.clone(),
                        format!(
                            "row {}, column {column}: {v} is not a finite number (the scene's \
                             values overflow; choose smaller ones)",
                            self.rows
                        ),
                    ));
                }
                Cell::Int(v) => record.push_field(&v.to_string()),
                // Shortest round trip; an exponent where the plain form would run to
                // hundreds of digits (1e300 was written as 301).
                Cell::Num(v) if v != 0.0 && !(1e-6..1e16).contains(&v.abs()) => {
                    record.push_field(&format!("{v:e}"))
                }
                Cell::Num(v) => record.push_field(&v.to_string()),
                Cell::Fixed(v, decimals) => record.push_field(&format!("{v:.decimals$}")),
                Cell::Text(t) => record.push_field(t),
            }
        }
        self.csv
            .write_record(&record)
            .map_err(|e| self.csv_error(e))
    }

    /// Flushes the table; returns the writer.
    pub fn finish(self) -> Result<W> {
        let path = self.path.clone();
        self.csv.into_inner().map_err(|e| Error::Write {
            path,
            source: std::io::Error::other(e.to_string()),
        })
    }
}

/// Writes a table to `path` atomically (no file unless every row was written).
pub fn write_file(
    path: &Path,
    what: &str,
    header: &[&str],
    fill: impl FnOnce(&mut TableWriter<&mut std::io::BufWriter<std::fs::File>>) -> Result<()>,
) -> Result<()> {
    crate::export::atomic::write_atomically(path, |w| {
        let mut table = TableWriter::new(w, what, path, header)?;
        fill(&mut table)?;
        table.finish().map(drop)
    })
}

/// A table as text.
pub fn to_string(
    what: &str,
    header: &[&str],
    fill: impl FnOnce(&mut TableWriter<&mut Vec<u8>>) -> Result<()>,
) -> Result<String> {
    let mut bytes = Vec::new();
    let mut table = TableWriter::new(&mut bytes, what, Path::new(what), header)?;
    fill(&mut table)?;
    table.finish()?;
    String::from_utf8(bytes).map_err(|e| Error::internal("CSV table", e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    const COLUMNS: [&str; 2] = ["x", "y"];

    fn values(text: &str) -> Result<Vec<Vec<f64>>> {
        Ok(read_numbers(text, "test", &COLUMNS)?
            .into_iter()
            .map(|r| r.values)
            .collect())
    }

    #[test]
    fn reads_what_spreadsheets_save() {
        // Excel's "CSV UTF-8": a BOM, CRLF, no header. The first row must not be lost.
        assert_eq!(
            values("\u{feff}0,0.5\r\n1,0.25\r\n").expect("reads"),
            vec![vec![0.0, 0.5], vec![1.0, 0.25]]
        );
        // Quoted cells, a header with a BOM, comments and blank lines.
        let rows = read_numbers(
            "\u{feff}\"x_m\",\"y_m\"\n# a note\n\n\"0\",\" 0.5 \"\n2,0\n",
            "test",
            &COLUMNS,
        )
        .expect("reads");
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0].values, vec![0.0, 0.5]);
        assert_eq!(rows[1].line, 5, "editor line numbers");
    }

    #[test]
    fn refuses_with_the_line_and_the_reason() {
        let err = values("x;y\n0;0,5\n").expect_err("semicolons").to_string();
        assert!(err.contains("line 1") && err.contains("';'"), "{err}");
        let err = values("0,1\n1,nan\n").expect_err("NaN").to_string();
        assert!(
            err.contains("line 2: the y NaN is not a finite number"),
            "{err}"
        );
        let err = values("0,1\n1,2,3\n").expect_err("three").to_string();
        assert!(
            err.contains("line 2: expected x, y; found 3 values"),
            "{err}"
        );
        let err = values("0,1\n1,a\n").expect_err("text").to_string();
        assert!(err.contains("line 2: \"1,a\" is not 2 numbers"), "{err}");
        let long = format!("0,1\n{},1\n", "9".repeat(5000) + "a");
        let err = values(&long).expect_err("long").to_string();
        assert!(err.len() < 400, "cut when echoed: {} bytes", err.len());
    }

    #[test]
    fn writes_units_quotes_and_refuses_non_finite_numbers() {
        let text = to_string("test table", &["name", "height_m", "n"], |t| {
            t.row(&[Cell::Text("a, b"), Cell::Fixed(1.5, 2), Cell::Int(3)])?;
            t.row(&[Cell::Text("c"), Cell::Num(0.1), Cell::Int(4)])
        })
        .expect("writes");
        assert_eq!(text, "name,height_m,n\n\"a, b\",1.50,3\nc,0.1,4\n");
        let text = to_string("test table", &["v"], |t| {
            t.row(&[Cell::Num(1e300)])?;
            t.row(&[Cell::Num(-2.5e-9)])?;
            t.row(&[Cell::Num(123456.75)])
        })
        .expect("writes");
        assert_eq!(text, "v\n1e300\n-2.5e-9\n123456.75\n");
        let err = to_string("test table", &["height_m"], |t| {
            t.row(&[Cell::Num(1.0)])?;
            t.row(&[Cell::Num(f64::INFINITY)])
        })
        .expect_err("inf refused")
        .to_string();
        assert!(err.contains("row 2, column height_m: inf"), "{err}");
    }
}
