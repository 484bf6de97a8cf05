//! Plain-text tables for listings (`objects`): every column as wide as its widest cell,
//! so long addresses and names never push a row out of line. Text only; knows nothing of
//! what the cells mean.

/// The lines of a table: the header, then each row; cells are separated by two spaces
/// and the last column is not padded.
pub fn table_lines(header: &[&str], rows: &[Vec<String>]) -> Vec<String> {
    // A cell from outside (a serial number, an answer) stays on its line and never acts
    // on the terminal.
    let rows: Vec<Vec<String>> = rows
        .iter()
        .map(|r| {
            r.iter()
                .map(|c| crate::report::visible_inline(c).into_owned())
                .collect()
        })
        .collect();
    let width = |i: usize| {
        rows.iter()
            .filter_map(|r| r.get(i))
            .map(|c| c.chars().count())
            .chain(header.get(i).map(|h| h.chars().count()))
            .max()
            .unwrap_or(0)
    };
    let widths: Vec<usize> = (0..header.len()).map(width).collect();
    let line = |cells: Vec<&str>| {
        let last = cells.len().saturating_sub(1);
        let mut s = String::new();
        for (i, cell) in cells.into_iter().enumerate() {
            s.push_str(cell);
            if i < last {
                let width = widths.get(i).copied().unwrap_or(0);
                let pad = width.saturating_sub(cell.chars().count()) + 2;
                s.extend(std::iter::repeat_n(' ', pad));
            }
        }
        s
    };
    let mut lines = vec![line(header.to_vec())];
    lines.extend(rows.iter().map(|r| line(r.iter().map(String::as_str).collect())));
    lines
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_are_as_wide_as_their_widest_cell() {
        let rows = vec![
            vec!["control_word_enable".to_string(), "#6.43".into(), "u8".into()],
            vec![
                "ident".to_string(),
                "index 22 (0x0016)".into(),
                "string(32)".into(),
            ],
        ];
        let lines = table_lines(&["name", "address", "type"], &rows);
        assert_eq!(
            lines,
            [
                "name                 address            type",
                "control_word_enable  #6.43              u8",
                "ident                index 22 (0x0016)  string(32)",
            ]
        );
    }
}
