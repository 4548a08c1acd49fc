//! The inputs of a factor's kernel in a host's layout.

use std::ops::Range;

use crate::host::{Host, HostFactor, HostManifold, HostPart};

/// One input array of a kernel in a host's layout.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum HostInput<M> {
    /// A constant field: its stored scalars.
    Constant {
        /// The field's name.
        field: &'static str,
        /// Its scalars' range in the factor's storage.
        stored: Range<usize>,
    },
    /// One host variable of a variable field: its parameters.
    Part {
        /// The field's name.
        field: &'static str,
        /// The variable's index among the factor's variables.
        variable: usize,
        /// The variable's stored scalars' range in the factor's storage.
        stored: Range<usize>,
        /// The host part.
        part: HostPart<M>,
        /// Its index among all host parts (the block's index).
        index: usize,
        /// Its tangent columns' range among all host parts' columns.
        columns: Range<usize>,
    },
}

impl<M: HostManifold> HostInput<M> {
    /// The input's name in a generated kernel: the field, or
    /// `<field>_<part>` for a named part.
    pub fn name(&self) -> String {
        match self {
            HostInput::Constant { field, .. } => (*field).to_owned(),
            HostInput::Part { field, part, .. } if part.name.is_empty() => (*field).to_owned(),
            HostInput::Part { field, part, .. } => format!("{field}_{}", part.name),
        }
    }

    /// The number of scalars the input holds.
    pub fn len(&self) -> usize {
        match self {
            HostInput::Constant { stored, .. } => stored.len(),
            HostInput::Part { part, .. } => part.manifold.parameters(),
        }
    }

    /// Whether the input holds no scalars.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A variable among a host kernel's inputs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HostVariable {
    /// The variable's index among the factor's variables.
    pub variable: usize,
    /// Its stored scalars' range in the factor's storage.
    pub stored: Range<usize>,
    /// Its host parts' range among all host parts.
    pub parts: Range<usize>,
}

/// The inputs and blocks of factor `F`'s kernel in host `H`'s layout.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HostLayout<M> {
    /// The input arrays in order.
    pub inputs: Vec<HostInput<M>>,
    /// The variables, in order, with where their parts are.
    pub variables: Vec<HostVariable>,
    /// The host parts in order (one Jacobian block each).
    pub parts: Vec<HostPart<M>>,
    /// The factor's stored scalars.
    pub stored: usize,
    /// The residual dimension.
    pub residual: usize,
}

impl<M: HostManifold> HostLayout<M> {
    /// The layout of factor `F` served to `H`.
    pub fn of<F: HostFactor<H>, H: Host<Manifold = M>>() -> Self {
        let mut inputs = Vec::new();
        let mut variables = Vec::new();
        let mut parts = Vec::new();
        let (mut offset, mut column) = (0, 0);
        for field in F::fields() {
            let stored = offset..offset + field.scalars;
            match field.variable {
                None => inputs.push(HostInput::Constant {
                    field: field.name,
                    stored: stored.clone(),
                }),
                Some(variable) => {
                    let first = parts.len();
                    for part in F::host_parts(variable) {
                        let dof = part.manifold.dof();
                        inputs.push(HostInput::Part {
                            field: field.name,
                            variable,
                            stored: stored.clone(),
                            part: *part,
                            index: parts.len(),
                            columns: column..column + dof,
                        });
                        parts.push(*part);
                        column += dof;
                    }
                    variables.push(HostVariable {
                        variable,
                        stored: stored.clone(),
                        parts: first..parts.len(),
                    });
                }
            }
            offset = stored.end;
        }
        HostLayout {
            inputs,
            variables,
            parts,
            stored: offset,
            residual: F::RESIDUAL_DIM,
        }
    }

    /// The total number of input scalars.
    pub fn input_len(&self) -> usize {
        self.inputs.iter().map(HostInput::len).sum()
    }

    /// The total number of tangent columns (the host parts' dofs).
    pub fn columns(&self) -> usize {
        self.parts.iter().map(|p| p.manifold.dof()).sum()
    }
}
