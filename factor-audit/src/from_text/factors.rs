//! The shipped factors a symbols file can sample: each gives its fields
//! (names and layouts, [`Factor::fields`]), seeded samples from
//! `factor-testing` and its own residual over any scalar
//! ([`Factor::perturbed_residual_over`] at a zero tangent).

use factor_core::Factor;
use factor_core::factor::FieldInfo;
use factor_core::scalar::Scalar;
use factor_core::storage::{Layout, Storage};
use factor_testing::samples::Sampler;
use slam_factors::{
    FreeLineFactor, LineReprojection, PlaneFactor, PluckerLineReprojection, PointReprojection,
};

/// A shipped factor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FactorKind {
    /// [`PointReprojection`].
    PointReprojection,
    /// [`LineReprojection`].
    LineReprojection,
    /// [`PluckerLineReprojection`].
    PluckerLineReprojection,
    /// [`PlaneFactor`].
    Plane,
    /// [`FreeLineFactor`].
    FreeLine,
}

const ALL: [FactorKind; 5] = [
    FactorKind::PointReprojection,
    FactorKind::LineReprojection,
    FactorKind::PluckerLineReprojection,
    FactorKind::Plane,
    FactorKind::FreeLine,
];

impl FactorKind {
    /// Its name ([`Factor::NAME`], as `slamjac list` shows it).
    pub fn name(self) -> &'static str {
        match self {
            FactorKind::PointReprojection => PointReprojection::NAME,
            FactorKind::LineReprojection => LineReprojection::NAME,
            FactorKind::PluckerLineReprojection => PluckerLineReprojection::NAME,
            FactorKind::Plane => PlaneFactor::NAME,
            FactorKind::FreeLine => FreeLineFactor::NAME,
        }
    }

    /// The factor named `name`.
    pub fn named(name: &str) -> Option<Self> {
        ALL.into_iter().find(|f| f.name() == name)
    }

    /// Every name, for messages.
    pub fn all_names() -> String {
        ALL.map(FactorKind::name).join(", ")
    }

    /// Its fields, in storage order.
    pub fn fields(self) -> Vec<FieldInfo> {
        match self {
            FactorKind::PointReprojection => PointReprojection::fields(),
            FactorKind::LineReprojection => LineReprojection::fields(),
            FactorKind::PluckerLineReprojection => PluckerLineReprojection::fields(),
            FactorKind::Plane => PlaneFactor::fields(),
            FactorKind::FreeLine => FreeLineFactor::fields(),
        }
    }

    /// Its storage layout (a record of its fields).
    pub fn layout(self) -> Layout {
        match self {
            FactorKind::PointReprojection => <PointReprojection as Storage<f64>>::layout(),
            FactorKind::LineReprojection => <LineReprojection as Storage<f64>>::layout(),
            FactorKind::PluckerLineReprojection => {
                <PluckerLineReprojection as Storage<f64>>::layout()
            }
            FactorKind::Plane => <PlaneFactor as Storage<f64>>::layout(),
            FactorKind::FreeLine => <FreeLineFactor as Storage<f64>>::layout(),
        }
    }

    /// One sample's stored scalars.
    pub fn sample(self, s: &mut Sampler) -> Vec<f64> {
        match self {
            FactorKind::PointReprojection => s.point_reprojection().to_scalars(),
            FactorKind::LineReprojection => s.line_reprojection().to_scalars(),
            FactorKind::PluckerLineReprojection => s.plucker_line_reprojection().to_scalars(),
            FactorKind::Plane => s.plane().to_scalars(),
            FactorKind::FreeLine => s.free_line().to_scalars(),
        }
    }

    /// The residual of the factor stored as `stored` (its own code).
    pub fn residual<S: Scalar>(self, stored: &[S]) -> Vec<S> {
        fn of<F: Factor, S: Scalar>(stored: &[S]) -> Vec<S> {
            F::perturbed_residual_over(&stored[..F::SCALARS], &vec![S::zero(); F::TANGENT_DIM])
        }
        match self {
            FactorKind::PointReprojection => of::<PointReprojection, S>(stored),
            FactorKind::LineReprojection => of::<LineReprojection, S>(stored),
            FactorKind::PluckerLineReprojection => of::<PluckerLineReprojection, S>(stored),
            FactorKind::Plane => of::<PlaneFactor, S>(stored),
            FactorKind::FreeLine => of::<FreeLineFactor, S>(stored),
        }
    }

    /// The residual's dimension.
    pub fn residual_dim(self) -> usize {
        match self {
            FactorKind::PointReprojection => PointReprojection::RESIDUAL_DIM,
            FactorKind::LineReprojection => LineReprojection::RESIDUAL_DIM,
            FactorKind::PluckerLineReprojection => PluckerLineReprojection::RESIDUAL_DIM,
            FactorKind::Plane => PlaneFactor::RESIDUAL_DIM,
            FactorKind::FreeLine => FreeLineFactor::RESIDUAL_DIM,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_residual_is_the_factors_own() {
        let f = Sampler::new(3).free_line();
        let r = FactorKind::FreeLine.residual(&f.to_scalars());
        let own = f.residual_dyn().unwrap();
        assert!((r[0] - own[0]).abs() < 1e-15 && (r[1] - own[1]).abs() < 1e-15);
        assert_eq!(FactorKind::named("free_line"), Some(FactorKind::FreeLine));
    }
}
