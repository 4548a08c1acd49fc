//! [`Columns`]: structure-of-arrays storage, one column of `len` scalars per
//! stored scalar of a factor (or per output entry).

use factor_core::Factor;

/// `width` columns of `len` scalars each, column after column in one
/// allocation: column `j` holds scalar `j` of every factor, factor `i` at
/// row `i`.
#[derive(Debug, Clone, PartialEq)]
pub struct Columns<S> {
    len: usize,
    data: Vec<S>,
}

impl<S: Copy + Default> Columns<S> {
    /// `width` columns of `len` zeros (`S::default()`).
    ///
    /// # Panics
    ///
    /// If `width · len` overflows `usize`.
    pub fn zeros(width: usize, len: usize) -> Self {
        let size = width.checked_mul(len).expect("width × len fits in memory");
        Columns {
            len,
            data: vec![S::default(); size],
        }
    }
}

impl<S> Columns<S> {
    /// Columns of `len` rows from their concatenation (`data.len()` a
    /// multiple of `len`; any number of columns when `len` is 0 and `data`
    /// is empty); `None` otherwise.
    pub fn from_vec(len: usize, data: Vec<S>) -> Option<Self> {
        // With no rows, only no data fits.
        data.len()
            .is_multiple_of(len)
            .then_some(Columns { len, data })
    }

    /// Rows: the number of factors.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether there are no rows.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The number of columns (0 when there are no rows).
    pub fn width(&self) -> usize {
        self.data.len().checked_div(self.len).unwrap_or(0)
    }

    /// Column `j`.
    ///
    /// # Panics
    ///
    /// If `j` is not below [`Columns::width`].
    pub fn column(&self, j: usize) -> &[S] {
        &self.data[j * self.len..(j + 1) * self.len]
    }

    /// Column `j`, mutably.
    ///
    /// # Panics
    ///
    /// If `j` is not below [`Columns::width`].
    pub fn column_mut(&mut self, j: usize) -> &mut [S] {
        &mut self.data[j * self.len..(j + 1) * self.len]
    }

    /// Every column, in order (none when there are no rows).
    pub fn columns(&self) -> impl Iterator<Item = &[S]> {
        self.data.chunks_exact(self.len.max(1))
    }

    /// Every column, mutably, in order (none when there are no rows).
    pub fn columns_mut(&mut self) -> impl Iterator<Item = &mut [S]> {
        self.data.chunks_exact_mut(self.len.max(1))
    }

    /// Row `i` across the columns: factor `i`'s scalars.
    ///
    /// # Panics
    ///
    /// If `i` is not below [`Columns::len`].
    pub fn row(&self, i: usize) -> Vec<S>
    where
        S: Copy,
    {
        assert!(i < self.len, "row {i} of {}", self.len);
        self.columns().map(|c| c[i]).collect()
    }

    /// The same columns with every scalar converted (`f64` to `f32`, say).
    pub fn map<T>(&self, f: impl FnMut(&S) -> T) -> Columns<T> {
        Columns {
            len: self.len,
            data: self.data.iter().map(f).collect(),
        }
    }
}

impl Columns<f64> {
    /// The inputs of a batch of factors of type `F`: one column per stored
    /// scalar, in [`Storage`](factor_core::Storage) order ([`Factor::fields`] gives the layout),
    /// factor `i` at row `i`.
    pub fn from_factors<F: Factor>(factors: &[F]) -> Self {
        let len = factors.len();
        let mut columns = Columns::zeros(F::SCALARS, len);
        let mut scalars = vec![0.0; F::SCALARS];
        for (i, factor) in factors.iter().enumerate() {
            factor.write_scalars(&mut scalars);
            for (j, s) in scalars.iter().enumerate() {
                columns.data[j * len + i] = *s;
            }
        }
        columns
    }
}
