//! One table, declared once and written as Markdown or as a LaTeX (booktabs) body: its columns
//! (the heading, alignment and decimals of each, in Markdown and, when LaTeX shows the column, in
//! LaTeX) and its rows of cells holding values, not text, so that each writer formats them its own
//! way (`±` or `\pm`, `–` or `--`).

use std::fmt::Write;

/// One column.
#[derive(Clone, Debug)]
pub struct Column {
    /// The Markdown heading.
    pub markdown: &'static str,
    /// Right-aligned in Markdown (`---:`), else `---`.
    pub right: bool,
    /// The LaTeX heading and alignment (`l`, `c`, `r`); `None`: LaTeX leaves the column out.
    pub latex: Option<(&'static str, char)>,
    /// Decimals of numbers in Markdown.
    pub decimals: usize,
    /// Decimals of numbers in LaTeX.
    pub latex_decimals: usize,
}

impl Column {
    /// A column of the Markdown table only, right-aligned, numbers with `decimals`.
    pub fn markdown(markdown: &'static str, decimals: usize) -> Self {
        Self {
            markdown,
            right: true,
            latex: None,
            decimals,
            latex_decimals: decimals,
        }
    }

    /// The same column aligned left in Markdown.
    pub fn left(self) -> Self {
        Self {
            right: false,
            ..self
        }
    }

    /// The same column in LaTeX too, headed `heading`, aligned `align`, numbers with `decimals`.
    pub fn latex(self, heading: &'static str, align: char, decimals: usize) -> Self {
        Self {
            latex: Some((heading, align)),
            latex_decimals: decimals,
            ..self
        }
    }
}

/// One cell's value.
#[derive(Clone, Debug)]
pub enum Cell {
    /// Text as it is (LaTeX escapes `_`, `%` and `&`).
    Text(String),
    /// A number with the column's decimals.
    Number(f64),
    /// A mean and the half-width of its interval, with the column's decimals.
    Interval(f64, f64),
    /// `n/of`.
    Count(usize, usize),
    /// No value: `–`.
    Missing,
}

/// A table: columns and rows of cells, one per column.
#[derive(Clone, Debug, Default)]
pub struct Table {
    /// The columns, left to right.
    pub columns: Vec<Column>,
    /// The rows, each a cell per column.
    pub rows: Vec<Vec<Cell>>,
}

impl Table {
    /// The Markdown table: heading, rule and rows, each line ending in a newline.
    pub fn markdown(&self) -> String {
        let mut out = self.markdown_head();
        for row in &self.rows {
            out.push_str(&self.markdown_row(row));
        }
        out
    }

    /// The Markdown heading and rule, each line ending in a newline: with
    /// [`markdown_row`](Self::markdown_row), a table printed row by row as its rows come.
    pub fn markdown_head(&self) -> String {
        let mut out = String::from("|");
        for column in &self.columns {
            let _ = write!(out, " {} |", column.markdown);
        }
        out.push_str("\n|");
        for column in &self.columns {
            out.push_str(if column.right { "---:|" } else { "---|" });
        }
        out.push('\n');
        out
    }

    /// One row of cells (one per column) as a Markdown line ending in a newline.
    pub fn markdown_row(&self, row: &[Cell]) -> String {
        let mut out = String::from("|");
        for (cell, column) in row.iter().zip(&self.columns) {
            let _ = write!(out, " {} |", markdown_cell(cell, column.decimals));
        }
        out.push('\n');
        out
    }

    /// The LaTeX column specification (`lrcc…`) of the columns LaTeX shows.
    pub fn latex_columns(&self) -> String {
        self.latex_shown()
            .filter_map(|c| c.latex)
            .map(|(_, align)| align)
            .collect()
    }

    /// The LaTeX heading and rows (booktabs rules between), of the columns LaTeX shows.
    pub fn latex_body(&self) -> String {
        let head: Vec<&str> = self
            .latex_shown()
            .filter_map(|c| c.latex)
            .map(|(heading, _)| heading)
            .collect();
        let mut out = format!("{} \\\\\n\\midrule\n", head.join(" & "));
        for row in &self.rows {
            let cells: Vec<String> = row
                .iter()
                .zip(&self.columns)
                .filter(|(_, column)| column.latex.is_some())
                .map(|(cell, column)| latex_cell(cell, column.latex_decimals))
                .collect();
            let _ = writeln!(out, "{} \\\\", cells.join(" & "));
        }
        out
    }

    fn latex_shown(&self) -> impl Iterator<Item = &Column> + '_ {
        self.columns.iter().filter(|c| c.latex.is_some())
    }
}

fn markdown_cell(cell: &Cell, decimals: usize) -> String {
    match cell {
        Cell::Text(text) => text.clone(),
        Cell::Number(value) => format!("{value:.decimals$}"),
        Cell::Interval(mean, half) => format!("{mean:.decimals$} ± {half:.decimals$}"),
        Cell::Count(n, of) => format!("{n}/{of}"),
        Cell::Missing => "–".to_string(),
    }
}

fn latex_cell(cell: &Cell, decimals: usize) -> String {
    match cell {
        Cell::Text(text) => tex(text),
        Cell::Number(value) => format!("{value:.decimals$}"),
        Cell::Interval(mean, half) => format!("${mean:.decimals$} \\pm {half:.decimals$}$"),
        Cell::Count(n, of) => format!("{n}/{of}"),
        Cell::Missing => "--".to_string(),
    }
}

/// `text` with LaTeX's special characters `_`, `%` and `&` escaped.
pub(super) fn tex(text: &str) -> String {
    text.replace('_', "\\_")
        .replace('%', "\\%")
        .replace('&', "\\&")
}

#[cfg(test)]
mod tests {
    use super::{Cell, Column, Table};

    #[test]
    fn one_declaration_gives_both_tables() {
        let table = Table {
            columns: vec![
                Column::markdown("policy", 0).left().latex("Policy", 'l', 0),
                Column::markdown("runs", 0),
                Column::markdown("picks per hour", 1).latex("Picks/h", 'r', 0),
            ],
            rows: vec![
                vec![
                    Cell::Text("push_mog".into()),
                    Cell::Count(3, 4),
                    Cell::Interval(250.04, 1.26),
                ],
                vec![Cell::Text("sog".into()), Cell::Number(4.0), Cell::Missing],
            ],
        };
        assert_eq!(
            table.markdown(),
            "| policy | runs | picks per hour |\n|---|---:|---:|\n\
             | push_mog | 3/4 | 250.0 ± 1.3 |\n| sog | 4 | – |\n"
        );
        assert_eq!(table.latex_columns(), "lr");
        assert_eq!(
            table.latex_body(),
            "Policy & Picks/h \\\\\n\\midrule\npush\\_mog & $250 \\pm 1$ \\\\\nsog & -- \\\\\n"
        );
    }
}
