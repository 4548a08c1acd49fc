//! Blocks printed over empty cells of an array: a block centred in a run
//! of empty cells (`~ \\ 0_{9×3} \\ ~` down a column, `\mathbf{I}_3`
//! amid blank cells, `& ~ & 0_{3×3} &` along a row) spans them, as the
//! reader sees it. Rows of nothing but empty cells are spacing. Which block
//! an empty cell belongs to is read from the nearest entry along its row or
//! column that no rule separates from it (a `|` of the column
//! specification, an `\hline`); the cell is left empty (an error of the
//! caller) when no entry or more than one direction could own it. The
//! blocks must tile the array in rectangles that nest as block rows and
//! block columns: the result is the matrix of those blocks.

use crate::ast::{Expr, Matrix};

/// An array's cells as printed, with its rules.
pub(super) struct Grid {
    /// The cells: `None` where nothing is printed, with the token index of
    /// the place (for an error).
    pub cells: Vec<Vec<Result<Expr, usize>>>,
    /// The column indices a `|` of the specification stands before.
    pub column_rules: Vec<usize>,
    /// The row indices an `\hline` stands before.
    pub row_rules: Vec<usize>,
}

/// The matrix the grid prints, or the token index of an empty cell no
/// block spans.
pub(super) fn resolve(grid: Grid) -> Result<Expr, usize> {
    let Grid {
        cells,
        column_rules,
        mut row_rules,
    } = grid;
    // Spacer rows go (an `\hline` before one stands before the next).
    let mut rows = Vec::with_capacity(cells.len());
    let mut rules = Vec::new();
    for (i, row) in cells.into_iter().enumerate() {
        let blank = row.iter().all(Result::is_err);
        if row_rules.contains(&i) {
            rules.push(rows.len());
        }
        if !blank {
            rows.push(row);
        }
    }
    row_rules = rules;
    let Some(first) = rows.first() else {
        return Err(0);
    };
    let width = first.len();
    if rows.iter().all(|r| r.iter().all(Result::is_ok)) || rows.iter().any(|r| r.len() != width) {
        // Nothing spans (rows of different lengths are the caller's to
        // judge).
        return rows
            .into_iter()
            .map(|r| r.into_iter().collect::<Result<Vec<_>, _>>())
            .collect::<Result<Vec<_>, _>>()
            .map(|rows| Expr::Matrix(Matrix { rows }));
    }
    let height = rows.len();
    let empty_at: Vec<Vec<Option<usize>>> = rows
        .iter()
        .map(|row| {
            row.iter()
                .map(|cell| cell.as_ref().err().copied())
                .collect()
        })
        .collect();
    let filled = |r: usize, c: usize| empty_at[r][c].is_none();
    // The owner of each cell: itself when filled.
    let mut owner = vec![vec![(0, 0); width]; height];
    for r in 0..height {
        for c in 0..width {
            owner[r][c] = if filled(r, c) {
                (r, c)
            } else {
                let along = |dr: isize, dc: isize| -> Option<(usize, usize)> {
                    let (mut i, mut j) = (r as isize, c as isize);
                    loop {
                        let (ni, nj) = (i + dr, j + dc);
                        if ni < 0 || nj < 0 || ni >= height as isize || nj >= width as isize {
                            return None;
                        }
                        // A `|` stands before the later column, an
                        // `\hline` before the later row.
                        let crossing = if dc != 0 {
                            column_rules.contains(&(j.max(nj) as usize))
                        } else {
                            row_rules.contains(&(i.max(ni) as usize))
                        };
                        if crossing {
                            return None;
                        }
                        (i, j) = (ni, nj);
                        if filled(i as usize, j as usize) {
                            return Some((i as usize, j as usize));
                        }
                    }
                };
                let across: Vec<_> = [along(0, -1), along(0, 1)].into_iter().flatten().collect();
                let down: Vec<_> = [along(-1, 0), along(1, 0)].into_iter().flatten().collect();
                match (across.as_slice(), down.as_slice()) {
                    ([one], []) | ([], [one]) => *one,
                    _ => return Err(empty_at[r][c].expect("an empty cell")),
                }
            };
        }
    }
    // Each block's rectangle holds only its own cells.
    let mut tiles = Vec::new();
    for r in 0..height {
        for c in 0..width {
            if !filled(r, c) {
                continue;
            }
            let mine: Vec<(usize, usize)> = (0..height)
                .flat_map(|i| (0..width).map(move |j| (i, j)))
                .filter(|&(i, j)| owner[i][j] == (r, c))
                .collect();
            let (r0, r1) = (
                mine.iter().map(|p| p.0).min().unwrap_or(r),
                mine.iter().map(|p| p.0).max().unwrap_or(r) + 1,
            );
            let (c0, c1) = (
                mine.iter().map(|p| p.1).min().unwrap_or(c),
                mine.iter().map(|p| p.1).max().unwrap_or(c) + 1,
            );
            if mine.len() != (r1 - r0) * (c1 - c0) {
                // Another block's cell inside the rectangle: the first
                // empty one of this block is reported.
                return Err(mine.iter().find_map(|&(i, j)| empty_at[i][j]).unwrap_or(0));
            }
            tiles.push(Tile {
                rows: (r0, r1),
                cols: (c0, c1),
                at: (r, c),
            });
        }
    }
    let mut entries: Vec<Vec<Option<Expr>>> = rows
        .into_iter()
        .map(|row| row.into_iter().map(Result::ok).collect())
        .collect();
    nest(&tiles, (0, height), (0, width), &mut entries).ok_or_else(|| {
        // No nesting: the first spanned cell is reported.
        empty_at.iter().flatten().find_map(|at| *at).unwrap_or(0)
    })
}

/// A block and the cells it spans (half-open ranges).
struct Tile {
    rows: (usize, usize),
    cols: (usize, usize),
    at: (usize, usize),
}

/// The block matrix of the tiles inside `rows × cols`: one tile is its
/// entry; else split into block rows along boundaries no tile crosses,
/// else into block columns; `None` when neither splits.
fn nest(
    tiles: &[Tile],
    rows: (usize, usize),
    cols: (usize, usize),
    entries: &mut [Vec<Option<Expr>>],
) -> Option<Expr> {
    let inside: Vec<&Tile> = tiles
        .iter()
        .filter(|t| {
            t.rows.0 >= rows.0 && t.rows.1 <= rows.1 && t.cols.0 >= cols.0 && t.cols.1 <= cols.1
        })
        .collect();
    if let [one] = inside.as_slice() {
        return entries[one.at.0][one.at.1].take();
    }
    let cuts = |range: (usize, usize), crossing: &dyn Fn(&Tile, usize) -> bool| -> Vec<usize> {
        (range.0 + 1..range.1)
            .filter(|&b| !inside.iter().any(|t| crossing(t, b)))
            .collect()
    };
    let row_cuts = cuts(rows, &|t, b| t.rows.0 < b && b < t.rows.1);
    if !row_cuts.is_empty() {
        let bounds: Vec<usize> = std::iter::once(rows.0)
            .chain(row_cuts)
            .chain(std::iter::once(rows.1))
            .collect();
        let mut out = Vec::new();
        for w in bounds.windows(2) {
            out.push(vec![nest(tiles, (w[0], w[1]), cols, entries)?]);
        }
        // Block rows of one block row each: the rows of the blocks.
        return Some(Expr::Matrix(Matrix {
            rows: out.into_iter().map(flatten_row).collect(),
        }));
    }
    let col_cuts = cuts(cols, &|t, b| t.cols.0 < b && b < t.cols.1);
    if col_cuts.is_empty() {
        return None;
    }
    let bounds: Vec<usize> = std::iter::once(cols.0)
        .chain(col_cuts)
        .chain(std::iter::once(cols.1))
        .collect();
    let mut row = Vec::new();
    for w in bounds.windows(2) {
        row.push(nest(tiles, rows, (w[0], w[1]), entries)?);
    }
    Some(Expr::Matrix(Matrix { rows: vec![row] }))
}

/// A block row holding one matrix of one row is that row's entries.
fn flatten_row(mut row: Vec<Expr>) -> Vec<Expr> {
    match row.pop() {
        Some(Expr::Matrix(Matrix { mut rows })) if rows.len() == 1 => rows.pop().expect("one row"),
        Some(other) => vec![other],
        None => Vec::new(),
    }
}
