//! One writer for every bench's output: its rows as a Markdown table, printed a row at a
//! time with the header before the first, or its report as one line of JSON.

use serde::Serialize;

/// A column: its heading, and whether it holds figures (aligned right) or words (left).
#[derive(Clone, Copy, Debug)]
pub(super) enum Column {
    /// Words: a name, a method, a setting.
    Text(&'static str),
    /// Figures: counts, times, shares.
    Figure(&'static str),
}

/// A Markdown table printed as its rows come: the header (and the alignment row) before
/// the first row, once.
#[derive(Debug)]
pub(super) struct Table {
    columns: Vec<Column>,
    started: bool,
}

impl Table {
    /// A table with these columns, nothing printed yet.
    pub(super) fn new(columns: &[Column]) -> Table {
        Table {
            columns: columns.to_vec(),
            started: false,
        }
    }

    /// The header and the alignment row, as printed before the first row.
    pub(super) fn header(&self) -> String {
        let names: Vec<&str> = self
            .columns
            .iter()
            .map(|c| match c {
                Column::Text(n) | Column::Figure(n) => *n,
            })
            .collect();
        let rule: String = self
            .columns
            .iter()
            .map(|c| match c {
                Column::Text(_) => "---|",
                Column::Figure(_) => "---:|",
            })
            .collect();
        format!("| {} |\n|{rule}", names.join(" | "))
    }

    /// Prints the header now, unless it was printed (a table with no rows yet).
    pub(super) fn start(&mut self) {
        if !std::mem::replace(&mut self.started, true) {
            println!("{}", self.header());
        }
    }

    /// Prints a row, and the header first if no row was printed yet.
    ///
    /// # Panics
    /// When `cells` does not hold one cell per column: a bench that prints a row out of
    /// step with its header is a bug, caught by its test.
    pub(super) fn row(&mut self, cells: &[String]) {
        assert_eq!(
            cells.len(),
            self.columns.len(),
            "a row of {} cells for {} columns",
            cells.len(),
            self.columns.len()
        );
        self.start();
        println!("| {} |", cells.join(" | "));
    }
}

/// Prints a report (or rows) as one line of JSON.
pub(super) fn json<T: Serialize + ?Sized>(report: &T) -> anyhow::Result<()> {
    println!("{}", serde_json::to_string(report)?);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_header_aligns_words_left_and_figures_right() {
        let t = Table::new(&[
            Column::Text("joint"),
            Column::Figure("bend"),
            Column::Text("kind"),
        ]);
        assert_eq!(t.header(), "| joint | bend | kind |\n|---|---:|---|");
    }
}
