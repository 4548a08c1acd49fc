//! Benchmark inputs: a few thousand sampled configurations, repeated to any
//! batch size (the kernels do the same work whatever the values, and the
//! memory traffic depends only on the size).

use factor_batch::Columns;

/// `base`'s rows repeated to `len` rows.
pub fn tiled<S: Copy>(base: &Columns<S>, len: usize) -> Columns<S> {
    let data = base
        .columns()
        .flat_map(|c| c.iter().copied().cycle().take(len))
        .collect();
    Columns::from_vec(len, data).expect("whole columns")
}
