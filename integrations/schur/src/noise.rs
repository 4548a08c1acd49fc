//! The noise models of a group's factors: the cost of factor `i` is
//! `½ ρ(‖Sᵢ rᵢ‖²)` with `Sᵢ` its square-root information
//! (`factor_core::noise::Noise`, the one noise model of every path).
//!
//! A fused kernel yields `Jᵀ w J`, `Jᵀ w r` and `½ w rᵀr` for a scalar
//! weight `w`, never `Jᵀ SᵀS J`; so
//!
//! - while every factor of the group is unit or isotropic (`S = I / σ`),
//!   the noise is the scalar `1/σ²` folded into the kernel's weight
//!   ([`Whitening::Scales`]): the fused kernels run unchanged;
//! - once one factor has per-component deviations or a full `S`, every
//!   factor of the group keeps its `S` ([`Whitening::Full`]) and the group
//!   linearizes through the per-lane Jacobian kernel, whitening `r` and `J`
//!   before it forms the normal blocks (`group::whitened`). Such factors
//!   are few in the problems here (one per plane seen by a camera).

use factor_core::noise::Noise;

/// The group's noise models, one per factor, in its factors' order.
#[derive(Debug, Clone)]
pub(crate) enum Whitening {
    /// `Sᵢ = √scaleᵢ · I`; empty while every factor is unit.
    Scales(Vec<f64>),
    /// Each factor's `S`, `dim × dim` row-major, end to end.
    Full { dim: usize, s: Vec<f64> },
}

impl Whitening {
    pub(crate) fn new() -> Self {
        Whitening::Scales(Vec::new())
    }

    /// Appends the noise of the `count`-th factor (those before it are
    /// already pushed), whose residual has `dim` entries.
    ///
    /// # Errors
    ///
    /// A model that does not fit the residual, or a deviation or entry
    /// that is not finite (a deviation must be above 0).
    pub(crate) fn push(&mut self, noise: &Noise, dim: usize, count: usize) -> Result<(), String> {
        noise.check(dim)?;
        let s: Vec<f64> = match noise {
            Noise::Unit | Noise::Sigma(_) => {
                let scale = match noise {
                    Noise::Sigma(sigma) => sigma.powi(-2),
                    _ => 1.0,
                };
                match self {
                    // The first scale other than 1 writes out the 1s
                    // before it.
                    Whitening::Scales(scales) if scale != 1.0 || !scales.is_empty() => {
                        scales.resize(count, 1.0);
                        scales.push(scale);
                    }
                    Whitening::Scales(_) => {}
                    Whitening::Full { s, .. } => s.extend(diagonal(&vec![scale.sqrt(); dim])),
                }
                return Ok(());
            }
            _ => {
                // Row-major.
                noise.sqrt_information(dim).transpose().as_slice().to_vec()
            }
        };
        if let Whitening::Scales(scales) = self {
            // Every factor so far as its S = √scale · I.
            let before: Vec<f64> = if scales.is_empty() {
                vec![1.0; count]
            } else {
                std::mem::take(scales)
            };
            let full = before
                .iter()
                .flat_map(|w| diagonal(&vec![w.sqrt(); dim]))
                .collect();
            *self = Whitening::Full { dim, s: full };
        }
        if let Whitening::Full { s: all, .. } = self {
            all.extend(s);
        }
        Ok(())
    }

    /// `‖Sᵢ r‖²` of factor `i`'s residual `r`.
    pub(crate) fn squared(&self, i: usize, r: &[f64]) -> f64 {
        let norm: f64 = r.iter().map(|x| x * x).sum();
        match self {
            Whitening::Scales(scales) if scales.is_empty() => norm,
            Whitening::Scales(scales) => scales[i] * norm,
            Whitening::Full { dim, s } => {
                let s = &s[i * dim * dim..(i + 1) * dim * dim];
                s.chunks(*dim)
                    .map(|row| {
                        let sr: f64 = row.iter().zip(r).map(|(a, b)| a * b).sum();
                        sr * sr
                    })
                    .sum()
            }
        }
    }

    /// Factor `i`'s `Sᵢ` (`dim × dim` row-major, `dim` its residual's
    /// length) into `out`.
    pub(crate) fn matrix_into(&self, i: usize, dim: usize, out: &mut [f64]) {
        match self {
            Whitening::Scales(scales) => {
                let root = if scales.is_empty() {
                    1.0
                } else {
                    scales[i].sqrt()
                };
                out.fill(0.0);
                for k in 0..dim {
                    out[k * dim + k] = root;
                }
            }
            Whitening::Full { dim, s } => {
                out.copy_from_slice(&s[i * dim * dim..(i + 1) * dim * dim]);
            }
        }
    }

    /// Puts factor `order[i]`'s model at `i`.
    pub(crate) fn reorder(&mut self, order: &[usize]) {
        match self {
            Whitening::Scales(scales) if !scales.is_empty() => {
                *scales = order.iter().map(|&i| scales[i]).collect();
            }
            Whitening::Scales(_) => {}
            Whitening::Full { dim, s } => {
                let n = *dim * *dim;
                *s = order
                    .iter()
                    .flat_map(|&i| s[i * n..(i + 1) * n].iter().copied())
                    .collect();
            }
        }
    }
}

/// The `d × d` diagonal matrix of `entries`, row-major.
fn diagonal(entries: &[f64]) -> Vec<f64> {
    let d = entries.len();
    let mut m = vec![0.0; d * d];
    for (k, x) in entries.iter().enumerate() {
        m[k * d + k] = *x;
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn isotropic_models_stay_scales_until_a_full_one_comes() {
        let mut w = Whitening::new();
        w.push(&Noise::Unit, 2, 0).unwrap();
        assert!(matches!(&w, Whitening::Scales(s) if s.is_empty()));
        w.push(&Noise::Sigma(0.5), 2, 1).unwrap();
        assert!(matches!(&w, Whitening::Scales(s) if s == &[1.0, 4.0]));
        let mut first = Whitening::new();
        first.push(&Noise::Sigma(2.0), 2, 0).unwrap();
        assert!(matches!(&first, Whitening::Scales(s) if s == &[0.25]));
        w.push(&Noise::Sigmas(vec![1.0, 0.25]), 2, 2).unwrap();
        let Whitening::Full { dim: 2, s } = &w else {
            panic!("{w:?}")
        };
        assert_eq!(
            s,
            &[1.0, 0.0, 0.0, 1.0, 2.0, 0.0, 0.0, 2.0, 1.0, 0.0, 0.0, 4.0]
        );
        assert_eq!(w.squared(1, &[3.0, 4.0]), 4.0 * 9.0 + 4.0 * 16.0);
        let mut s = [0.0; 4];
        w.matrix_into(2, 2, &mut s);
        assert_eq!(s, [1.0, 0.0, 0.0, 4.0]);
        let mut isotropic = Whitening::new();
        isotropic.push(&Noise::Sigma(0.5), 2, 0).unwrap();
        assert_eq!(isotropic.squared(0, &[3.0, 4.0]), 100.0);
        isotropic.matrix_into(0, 2, &mut s);
        assert_eq!(s, [2.0, 0.0, 0.0, 2.0]);
        w.reorder(&[2, 0, 1]);
        let Whitening::Full { s, .. } = &w else {
            panic!("{w:?}")
        };
        assert_eq!(&s[..4], &[1.0, 0.0, 0.0, 4.0]);
        assert!(w.push(&Noise::Sigma(0.0), 2, 3).is_err());
        assert!(w.push(&Noise::Sigmas(vec![1.0]), 2, 3).is_err());
    }
}
