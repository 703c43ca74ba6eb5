//! One markdown table writer for the lab's reports: header cells, then rows, rendered
//! as `| a | b |` lines under a `|---|---|` rule. Commands compute into structs and
//! render through it (as [`crate::soak::SoakReport::summary`] renders apart).

/// A markdown table: its header and its rows of cells.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Table {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    /// A table with these column headers and no row yet.
    pub fn new<S: Into<String>>(header: impl IntoIterator<Item = S>) -> Self {
        Self {
            header: header.into_iter().map(Into::into).collect(),
            rows: Vec::new(),
        }
    }

    /// Append a row (its cells, in column order; an empty cell stays empty).
    pub fn row<S: Into<String>>(&mut self, cells: impl IntoIterator<Item = S>) {
        self.rows.push(cells.into_iter().map(Into::into).collect());
    }

    /// The table as markdown, one line per row, each ending in a newline.
    pub fn render(&self) -> String {
        let mut out = line(&self.header);
        out.push('|');
        for _ in &self.header {
            out.push_str("---|");
        }
        out.push('\n');
        for r in &self.rows {
            out.push_str(&line(r));
        }
        out
    }
}

/// `| a | b |` (an empty cell as `| |`), with its newline.
fn line(cells: &[String]) -> String {
    let mut out = String::from("|");
    for c in cells {
        if c.is_empty() {
            out.push_str(" |");
        } else {
            out.push(' ');
            out.push_str(c);
            out.push_str(" |");
        }
    }
    out.push('\n');
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renders_markdown_with_empty_cells_kept() {
        let mut t = Table::new(["name", "value", "note"]);
        t.row(["a", "1", ""]);
        t.row(["**all**".to_string(), String::new(), "x".to_string()]);
        assert_eq!(
            t.render(),
            "| name | value | note |\n|---|---|---|\n| a | 1 | |\n| **all** | | x |\n"
        );
    }
}
