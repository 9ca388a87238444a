//! CSV tables a scenario's world refers to (plants, centre lines, posts):
//! a header line naming the columns, then one record a line; `#` comments
//! and blank lines skipped. Every error names the file, the line and the
//! column ([`ScenarioError::Table`]).

use std::path::Path;

use crate::error::{ScenarioError, TableError};

use super::check::Checker;

/// One record: its line in the file (from 1) and its cells, trimmed.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// Line in the file, from 1.
    pub line: usize,
    cells: Vec<String>,
}

/// A CSV file read for the field `field` of scenario `origin`.
#[derive(Debug, Clone)]
pub struct Table<'a> {
    check: Checker<'a>,
    field: String,
    file: String,
    header_line: usize,
    header: Vec<String>,
    /// The records, in file order.
    pub records: Vec<Record>,
}

impl<'a> Table<'a> {
    /// Reads `name` (relative to `base_dir`, the scenario file's folder) for
    /// `field`; its columns must be among `known`.
    ///
    /// # Errors
    /// A built-in scenario (no folder), an unreadable file, no header, an
    /// unknown or repeated column, a record of the wrong number of cells, a
    /// file without records.
    pub fn read(
        name: &str,
        base_dir: Option<&Path>,
        field: &str,
        known: &[&str],
        check: Checker<'a>,
    ) -> Result<Self, ScenarioError> {
        let Some(dir) = base_dir else {
            return Err(check.error(
                field,
                "a built-in scenario cannot refer to a file; run it from a scenario file",
            ));
        };
        let path = dir.join(name);
        let text = std::fs::read_to_string(&path)
            .map_err(|source| ScenarioError::Read { file: path, source })?;
        Self::parse(&text, name, field, known, check)
    }

    /// Parses `text`, the contents of the file `name` (see [`Self::read`]).
    ///
    /// # Errors
    /// As [`Self::read`], but for reading.
    pub fn parse(
        text: &str,
        name: &str,
        field: &str,
        known: &[&str],
        check: Checker<'a>,
    ) -> Result<Self, ScenarioError> {
        let mut table = Self {
            check,
            field: field.to_owned(),
            file: name.to_owned(),
            header_line: 0,
            header: Vec::new(),
            records: Vec::new(),
        };
        for (i, raw) in text.lines().enumerate() {
            let line = raw.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let cells: Vec<String> = line.split(',').map(|c| c.trim().to_owned()).collect();
            if table.header_line == 0 {
                table.header_line = i + 1;
                for (k, c) in cells.iter().enumerate() {
                    if !known.contains(&c.as_str()) {
                        return Err(table.at(
                            i + 1,
                            k,
                            &format!("unknown column `{c}`; the columns are {}", known.join(", ")),
                        ));
                    }
                    if cells.get(..k).is_some_and(|before| before.contains(c)) {
                        return Err(table.at(i + 1, k, &format!("column `{c}` repeated")));
                    }
                }
                table.header = cells;
                continue;
            }
            if cells.len() != table.header.len() {
                let k = cells.len().min(table.header.len());
                return Err(table.at(
                    i + 1,
                    k,
                    &format!(
                        "{} cells where the header has {}",
                        cells.len(),
                        table.header.len()
                    ),
                ));
            }
            table.records.push(Record { line: i + 1, cells });
        }
        if table.header_line == 0 {
            return Err(check.error(field, &format!("{name}: no header line")));
        }
        if table.records.is_empty() {
            return Err(table.at(table.header_line, 0, "no record after the header"));
        }
        Ok(table)
    }

    /// The error at `line` in column `k` (from 0), with `reason`.
    #[must_use]
    pub fn at(&self, line: usize, k: usize, reason: &str) -> ScenarioError {
        let name = self.header.get(k).cloned().unwrap_or_default();
        ScenarioError::Table(Box::new(TableError {
            origin: self.check.origin().to_owned(),
            field: self.field.clone(),
            file: self.file.clone(),
            line,
            column: (k + 1, name),
            reason: reason.to_owned(),
        }))
    }

    /// The index of the column `name`, if the header has it.
    #[must_use]
    pub fn optional(&self, name: &str) -> Option<usize> {
        self.header.iter().position(|h| h == name)
    }

    /// The index of the column `name`.
    ///
    /// # Errors
    /// The header lacks it (the error names the header line).
    pub fn column(&self, name: &str) -> Result<usize, ScenarioError> {
        self.optional(name).ok_or_else(|| {
            let mut e = self.at(
                self.header_line,
                self.header.len(),
                &format!("missing column `{name}`"),
            );
            if let ScenarioError::Table(t) = &mut e {
                t.column.1 = name.to_owned();
            }
            e
        })
    }

    /// The text of column `k` of `record`.
    #[must_use]
    pub fn text<'r>(&self, record: &'r Record, k: usize) -> &'r str {
        record.cells.get(k).map_or("", String::as_str)
    }

    /// The finite number in column `k` of `record`, within `[lo, hi]`.
    ///
    /// # Errors
    /// Not a number, not finite, or out of range.
    pub fn number(
        &self,
        record: &Record,
        k: usize,
        lo: f64,
        hi: f64,
    ) -> Result<f64, ScenarioError> {
        let text = self.text(record, k);
        match text.parse::<f64>() {
            Ok(v) if v.is_finite() && v >= lo && v <= hi => Ok(v),
            Ok(v) if v.is_finite() => Err(self.at(
                record.line,
                k,
                &format!("must be within [{lo}, {hi}], got {v}"),
            )),
            _ => Err(self.at(record.line, k, &format!("`{text}` is not a finite number"))),
        }
    }

    /// The points of the columns `x_m`, `y_m` (within ±10⁶ m), with their lines.
    ///
    /// # Errors
    /// A missing column or a bad cell.
    pub fn points(&self) -> Result<Vec<(usize, [f64; 2])>, ScenarioError> {
        let (x, y) = (self.column("x_m")?, self.column("y_m")?);
        self.records
            .iter()
            .map(|r| {
                Ok((
                    r.line,
                    [self.number(r, x, -1e6, 1e6)?, self.number(r, y, -1e6, 1e6)?],
                ))
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const KNOWN: &[&str] = &["x_m", "y_m", "radius_m"];

    fn parse(text: &str) -> Result<Table<'static>, ScenarioError> {
        Table::parse(
            text,
            "p.csv",
            "world.plants_csv",
            KNOWN,
            Checker::new("s.toml"),
        )
    }

    #[test]
    fn records_keep_their_lines_and_cells_are_checked_where_they_are() {
        let t = parse("# plants\nx_m, y_m\n\n1, 2\n3,4\n").unwrap();
        assert_eq!(t.points().unwrap(), vec![(4, [1.0, 2.0]), (5, [3.0, 4.0])]);
        let t = parse("x_m,y_m\n1,2\n3,four\n").unwrap();
        let e = t.points().unwrap_err();
        assert_eq!(e.cell(), Some(("p.csv", 3, 2)));
        assert_eq!(e.field(), Some("world.plants_csv"));
        assert!(e.to_string().contains("p.csv:3:2 (column `y_m`)"), "{e}");
        let e = parse("x_m\n1\n").unwrap().points().unwrap_err();
        assert_eq!(e.cell(), Some(("p.csv", 1, 2)));
        assert!(e.to_string().contains("missing column `y_m`"), "{e}");
        let e = parse("x_m,z_m\n1,2\n").unwrap_err();
        assert_eq!(e.cell(), Some(("p.csv", 1, 2)));
        let e = parse("x_m,y_m\n1,2,3\n").unwrap_err();
        assert_eq!(e.cell(), Some(("p.csv", 2, 3)));
        let e = parse("x_m,x_m\n1,2\n").unwrap_err();
        assert!(e.to_string().contains("repeated"), "{e}");
        assert!(parse("x_m,y_m\n").is_err());
        assert!(parse("").is_err());
        let e = parse("x_m,y_m\n1,inf\n").unwrap().points().unwrap_err();
        assert_eq!(e.cell(), Some(("p.csv", 2, 2)));
    }
}
