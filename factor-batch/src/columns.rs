//! [`Columns`]: structure-of-arrays storage, one column of `len` scalars per
//! stored scalar of a factor (or per output entry).

use factor_core::Factor;

/// `width` columns of `len` scalars each, column after column in one
/// allocation: column `j` holds scalar `j` of every factor, factor `i` at
/// row `i`.
///
/// Columns made here ([`Columns::zeros`], [`Columns::from_factors`]) start
/// an odd number of 64-byte cache lines apart: laid end to end, columns of
/// `512·k` `f64` rows put row `i` of every column in the same L1 cache set,
/// and such batches ran 2–4× slower.
#[derive(Debug, Clone)]
pub struct Columns<S> {
    len: usize,
    /// Scalars from the start of one column to the start of the next.
    stride: usize,
    data: Vec<S>,
}

/// Two column sets are equal when their rows and columns are, whatever
/// their padding.
impl<S: PartialEq> PartialEq for Columns<S> {
    fn eq(&self, other: &Self) -> bool {
        self.len == other.len && self.columns().eq(other.columns())
    }
}

/// `len` rounded up to a whole and odd number of 64-byte cache lines of `S`.
fn padded_stride<S>(len: usize) -> usize {
    let per_line = (64 / core::mem::size_of::<S>().max(1)).max(1);
    let lines = len.div_ceil(per_line);
    (lines + usize::from(lines.is_multiple_of(2) && lines > 0)) * per_line
}

impl<S: Copy + Default> Columns<S> {
    /// `width` columns of `len` zeros (`S::default()`).
    ///
    /// # Panics
    ///
    /// If `width · len` overflows `usize`.
    pub fn zeros(width: usize, len: usize) -> Self {
        let stride = padded_stride::<S>(len);
        let size = width
            .checked_mul(stride)
            .expect("width × len fits in memory");
        Columns {
            len,
            stride,
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
        data.len().is_multiple_of(len).then_some(Columns {
            len,
            stride: len,
            data,
        })
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
        self.data.len().checked_div(self.stride).unwrap_or(0)
    }

    /// Column `j`.
    ///
    /// # Panics
    ///
    /// If `j` is not below [`Columns::width`].
    pub fn column(&self, j: usize) -> &[S] {
        &self.data[j * self.stride..j * self.stride + self.len]
    }

    /// Column `j`, mutably.
    ///
    /// # Panics
    ///
    /// If `j` is not below [`Columns::width`].
    pub fn column_mut(&mut self, j: usize) -> &mut [S] {
        &mut self.data[j * self.stride..j * self.stride + self.len]
    }

    /// Every column, in order (none when there are no rows).
    pub fn columns(&self) -> impl Iterator<Item = &[S]> {
        let len = self.len;
        self.data
            .chunks_exact(self.stride.max(1))
            .map(move |c| &c[..len])
    }

    /// Every column, mutably, in order (none when there are no rows).
    pub fn columns_mut(&mut self) -> impl Iterator<Item = &mut [S]> {
        let len = self.len;
        self.data
            .chunks_exact_mut(self.stride.max(1))
            .map(move |c| &mut c[..len])
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
            stride: self.stride,
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
                columns.data[j * columns.stride + i] = *s;
            }
        }
        columns
    }
}

#[cfg(test)]
mod tests {
    use super::Columns;

    #[test]
    fn columns_start_an_odd_number_of_cache_lines_apart() {
        for len in [1, 7, 8, 9, 512, 1000, 1024, 4096] {
            let mut c = Columns::<f64>::zeros(3, len);
            let gap = c.column(1).as_ptr() as usize - c.column(0).as_ptr() as usize;
            assert!(
                gap >= 8 * len && gap.is_multiple_of(64) && (gap / 64) % 2 == 1,
                "{len}: {gap}"
            );
            c.column_mut(2)[len - 1] = 1.0;
            assert_eq!(c.width(), 3);
            assert_eq!(c.columns().map(<[f64]>::len).collect::<Vec<_>>(), [len; 3]);
            // Equal to the same values packed end to end.
            let mut packed = vec![0.0; 3 * len];
            packed[3 * len - 1] = 1.0;
            assert_eq!(Columns::from_vec(len, packed).unwrap(), c);
        }
        let empty = Columns::<f64>::zeros(4, 0);
        assert_eq!((empty.width(), empty.columns().count()), (0, 0));
    }
}
