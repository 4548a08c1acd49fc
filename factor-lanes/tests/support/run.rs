//! Running a kernel over many configurations, in lanes or one at a time.

use super::lanes::Lanes;
use super::scalar_reference::{Functions, Scalar};
use crate::Real;

/// A kernel with its inputs and outputs each concatenated into one slice.
pub type Kernel<T> = fn(&[T]) -> Vec<T>;

/// The outputs of `kernel` for every configuration (inputs as `f64`, rounded
/// to the lane scalar), `L::N` configurations per call; the count must be a
/// multiple of `L::N`.
pub fn in_lanes<L: Lanes + Real>(configurations: &[Vec<f64>], kernel: Kernel<L>) -> Vec<Vec<L::S>> {
    assert_eq!(configurations.len() % L::N, 0, "whole groups of lanes");
    let mut outputs = Vec::with_capacity(configurations.len());
    for group in configurations.chunks(L::N) {
        let inputs: Vec<L> = (0..group[0].len())
            .map(|i| L::from_lanes(&group.iter().map(|c| L::scalar(c[i])).collect::<Vec<_>>()))
            .collect();
        let lanes: Vec<Vec<L::S>> = kernel(&inputs).into_iter().map(L::lanes).collect();
        outputs.extend((0..L::N).map(|k| lanes.iter().map(|o| o[k]).collect::<Vec<_>>()));
    }
    outputs
}

/// The outputs of `kernel` for every configuration, one at a time, with the
/// scalar of `L` and the functions of `F`.
pub fn one_by_one<L: Lanes, F: Functions<L::S>>(
    configurations: &[Vec<f64>],
    kernel: Kernel<Scalar<L::S, F>>,
) -> Vec<Vec<L::S>>
where
    L::S: Real + PartialOrd,
{
    configurations
        .iter()
        .map(|c| {
            let inputs: Vec<_> = c.iter().map(|&x| Scalar::new(L::scalar(x))).collect();
            kernel(&inputs).into_iter().map(|o| o.0).collect()
        })
        .collect()
}
