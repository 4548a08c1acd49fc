//! How the factors and variables of a problem are laid out, below the
//! passes and the structure that read them: a factor type's variable slots
//! ([`SlotInfo`]), a variable's storage and chart ([`Variable`],
//! [`Chart`]), the limits of a factor's size, and the factors' topology
//! ([`Topology`]: which variables each factor names), which the structure
//! of the reduced system is computed from.

use factor_core::Factor;
use factor_core::manifold::Perturbation;

/// The lane type of the batches (4 × `f64`: see the crate documentation).
pub type Lane = factor_lanes::F64x4;

/// A variable slot of a factor type, as the factor declares it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct SlotInfo {
    pub(crate) factor: &'static str,
    pub(crate) name: &'static str,
    /// Stored scalars and tangent dimension.
    pub(crate) scalars: usize,
    pub(crate) tangent: usize,
    type_name: &'static str,
    perturbation: Perturbation,
    description: &'static str,
}

impl SlotInfo {
    /// Each variable slot of `F`.
    pub(crate) fn of<F: Factor>() -> Vec<SlotInfo> {
        let scalars = F::fields()
            .into_iter()
            .filter(|f| f.variable.is_some())
            .map(|f| f.scalars);
        F::variables()
            .into_iter()
            .zip(scalars)
            .map(|(info, scalars)| SlotInfo {
                factor: F::NAME,
                name: info.name,
                scalars,
                tangent: info.tangent_dim,
                type_name: info.type_name,
                perturbation: info.perturbation,
                description: info.tangent,
            })
            .collect()
    }

    /// Whether a variable in both slots is perturbed the same way.
    pub(crate) fn same_chart(&self, other: &SlotInfo) -> bool {
        (
            self.tangent,
            self.type_name,
            self.perturbation,
            self.description,
        ) == (
            other.tangent,
            other.type_name,
            other.perturbation,
            other.description,
        )
    }

    /// `factor declares it `type` (side: tangent)`.
    pub(crate) fn describe(&self) -> String {
        // Most tangents' descriptions begin with their side already.
        let side = self.perturbation.as_str();
        let how = if self.description.starts_with(side) {
            self.description.to_owned()
        } else {
            format!("{side}: {}", self.description)
        };
        format!("{} declares it `{}` ({how})", self.factor, self.type_name)
    }
}

/// How the factors on a variable perturb it: as the slot `slot` of group
/// `group` (the first factor that named it) declares it, which every other
/// factor on it must match; that factor type's [`Factor::with_retracted`]
/// retracts it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Chart {
    pub(crate) group: usize,
    pub(crate) slot: usize,
    /// Tangent dimension.
    pub(crate) tangent: usize,
}

/// A variable: where its stored scalars are, and its role.
#[derive(Debug, Clone)]
pub(crate) struct Variable {
    pub(crate) offset: usize,
    pub(crate) scalars: usize,
    pub(crate) fixed: bool,
    pub(crate) eliminated: bool,
    pub(crate) chart: Option<Chart>,
}

/// The most variables a factor may have.
pub(crate) const MAX_SLOTS: usize = 8;
/// The most stored scalars a factor may have.
pub(crate) const MAX_SCALARS: usize = 128;

/// The factors of one type as the structure of the reduced system sees
/// them: their variables, which it may reorder and rename, and where each
/// factor's normal-equation blocks go.
pub(crate) trait Topology {
    /// The factor's name.
    fn name(&self) -> &'static str;
    /// The number of factors.
    fn len(&self) -> usize;
    /// Variables per factor.
    fn slots(&self) -> usize;
    /// Each variable slot, as the factor declares it.
    fn slot_info(&self) -> &[SlotInfo];
    /// Every factor's variable ids, `slots()` per factor.
    fn variable_ids(&self) -> &[u32];
    /// Puts factor `order[i]` at `i`, each variable `id` renamed
    /// `rename[id]`.
    fn reorder(&mut self, order: &[usize], rename: &[u32]);
    /// Each factor's block targets
    /// ([`Structure`](crate::structure::Structure)), one per pair of slots.
    fn set_targets(&mut self, targets: Vec<u32>);
}
