//! The generated crate's sources: `src/lib.rs`, `src/real.rs` (the float
//! trait), `src/shape.rs` (the kernels' array lengths) and one
//! `src/<module>.rs` per kernel, written or compared with what is on disk
//! ([`GeneratedCrate`]).
//!
//! `Cargo.toml` and any other file outside `src/` are hand-written and left
//! alone. The sources use one feature the manifest declares, `lanes`, which
//! brings the optional dependency `factor-lanes` (package `factor-generated`
//! and a user's kernel crate alike):
//!
//! ```toml
//! [dependencies]
//! factor-lanes = { path = "…/factor-lanes", optional = true }
//!
//! [features]
//! lanes = ["dep:factor-lanes"]
//! ```
//!
//! With it, `real.rs` implements `Real` for the lane types
//! (`factor_lanes::impl_real!`) and each module's marker `Kernel` implements
//! `factor_lanes::Kernel` (and `NormalKernel`); without it the crate has no
//! dependencies. The files name the generator of the modules'
//! [`Provenance`].

use std::io;
use std::path::{Path, PathBuf};

use crate::error::CodegenError;
use crate::module::{GeneratedModule, generate_with};
use crate::spec::{KernelSpec, Provenance};
use crate::tree;

/// `src/real.rs` after its header: the float trait and its `f32` and `f64`
/// implementations.
const REAL_BODY: &str = r#"
use core::ops::{Add, Div, Mul, Neg, Sub};

/// A number the kernels compute with: `f32`, `f64`, or a SIMD type whose
/// lanes hold several configurations (with the crate's `lanes` feature, the
/// lane types of `factor-lanes`).
///
/// Beyond the arithmetic operators a kernel needs literals, square roots,
/// the math-library functions `sin`, `cos`, `atan2`, `exp`, `ln`, `acos`,
/// `asin`, `atan` and one branching primitive, [`Real::select_lt`],
/// which a SIMD type implements as a lane-wise select. Kernels evaluate both
/// arms of a branch before selecting, so an arm that is not selected may be
/// non-finite.
pub trait Real:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// The literal `c`, rounded to the type.
    fn constant(c: f64) -> Self;
    /// Square root.
    fn sqrt(self) -> Self;
    /// Sine.
    fn sin(self) -> Self;
    /// Cosine.
    fn cos(self) -> Self;
    /// Four-quadrant arc tangent of `self / x` (`self` is the ordinate).
    fn atan2(self, x: Self) -> Self;
    /// `e^self`.
    fn exp(self) -> Self;
    /// Natural logarithm.
    fn ln(self) -> Self;
    /// Arc cosine, in `[0, π]`.
    fn acos(self) -> Self;
    /// Arc sine, in `[−π/2, π/2]`.
    fn asin(self) -> Self;
    /// Arc tangent, in `(−π/2, π/2)`.
    fn atan(self) -> Self;
    /// `if lhs < rhs { if_less } else { otherwise }`.
    fn select_lt(lhs: Self, rhs: Self, if_less: Self, otherwise: Self) -> Self;
}

impl Real for f64 {
    #[inline]
    fn constant(c: f64) -> Self {
        c
    }
    #[inline]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline]
    fn sin(self) -> Self {
        f64::sin(self)
    }
    #[inline]
    fn cos(self) -> Self {
        f64::cos(self)
    }
    #[inline]
    fn atan2(self, x: Self) -> Self {
        f64::atan2(self, x)
    }
    #[inline]
    fn exp(self) -> Self {
        f64::exp(self)
    }
    #[inline]
    fn ln(self) -> Self {
        f64::ln(self)
    }
    #[inline]
    fn acos(self) -> Self {
        f64::acos(self)
    }
    #[inline]
    fn asin(self) -> Self {
        f64::asin(self)
    }
    #[inline]
    fn atan(self) -> Self {
        f64::atan(self)
    }
    #[inline]
    fn select_lt(lhs: Self, rhs: Self, if_less: Self, otherwise: Self) -> Self {
        if lhs < rhs { if_less } else { otherwise }
    }
}

impl Real for f32 {
    #[inline]
    fn constant(c: f64) -> Self {
        c as f32
    }
    #[inline]
    fn sqrt(self) -> Self {
        f32::sqrt(self)
    }
    #[inline]
    fn sin(self) -> Self {
        f32::sin(self)
    }
    #[inline]
    fn cos(self) -> Self {
        f32::cos(self)
    }
    #[inline]
    fn atan2(self, x: Self) -> Self {
        f32::atan2(self, x)
    }
    #[inline]
    fn exp(self) -> Self {
        f32::exp(self)
    }
    #[inline]
    fn ln(self) -> Self {
        f32::ln(self)
    }
    #[inline]
    fn acos(self) -> Self {
        f32::acos(self)
    }
    #[inline]
    fn asin(self) -> Self {
        f32::asin(self)
    }
    #[inline]
    fn atan(self) -> Self {
        f32::atan(self)
    }
    #[inline]
    fn select_lt(lhs: Self, rhs: Self, if_less: Self, otherwise: Self) -> Self {
        if lhs < rhs { if_less } else { otherwise }
    }
}

// The SIMD lane types of `factor-lanes` (`F64x4`, `F32x8`, `F64x8`), with the
// crate's `lanes` feature.
#[cfg(feature = "lanes")]
factor_lanes::impl_real!(crate::Real);
"#;

/// `src/real.rs`: the float trait and its `f32` and `f64` implementations.
fn real_source(provenance: &Provenance) -> String {
    format!(
        "//! The float trait the kernels are generic over.\n\
         //!\n\
         //! Generated by `{}`; do not edit.\n{REAL_BODY}",
        provenance.generate
    )
}

/// `src/lib.rs` for `modules`: crate documentation (the provenance's
/// description and "do not edit" note) with a table of the kernels, the
/// lints, the module list and `pub use real::Real`.
fn lib_source(provenance: &Provenance, modules: &[GeneratedModule]) -> String {
    let mut sorted: Vec<&GeneratedModule> = modules.iter().collect();
    sorted.sort_by_key(|m| m.name);
    let mut out = String::new();
    for line in provenance.description.lines() {
        if line.is_empty() {
            out.push_str("//!\n");
        } else {
            out.push_str(&format!("//! {line}\n"));
        }
    }
    out.push_str(&format!(
        "//!\n\
         //! Generated by `{}`; do not edit. `{}` fails when these\n\
         //! sources differ from what the factor definitions produce.\n",
        provenance.generate, provenance.check
    ));
    out.push_str(
        "//!\n\
         //! Each module holds one function of the same name: straight-line code over\n\
         //! fixed-size arrays that writes the residual and each requested Jacobian block\n\
         //! (row-major, residual rows × tangent columns), sharing common subexpressions\n\
         //! and skipping the work of the blocks passed as `None`. The crate has no\n\
         //! dependencies, no `unsafe`, no allocation and no panics; the kernels are\n\
         //! generic over [`Real`], implemented for `f32` and `f64`. The feature\n\
         //! `lanes` (optional dependency `factor-lanes`) implements it for the SIMD\n\
         //! lane types `F64x4`, `F32x8` and `F64x8`, which evaluate several\n\
         //! configurations at once, and makes each module's marker `Kernel` a\n\
         //! `factor_lanes::Kernel`, the entry of batch evaluators (`factor-batch`).\n",
    );
    let normal = modules.iter().any(|m| m.normal_counts.is_some());
    if normal {
        out.push_str(
            "//!\n\
             //! A module generated with normal equations also holds `<name>_normal`: the\n\
             //! cost `½ w rᵀr`, the gradient blocks `Jᵢᵀ w r` and the upper triangle of\n\
             //! `JᵀwJ` for a per-factor weight `w`, fused with the Jacobian.\n",
        );
    }
    out.push_str(if normal {
        "//!\n\
         //! | kernel | factor | operations | residual only | normal equations |\n\
         //! | --- | --- | --- | --- | --- |\n"
    } else {
        "//!\n\
         //! | kernel | factor | operations | residual only |\n\
         //! | --- | --- | --- | --- |\n"
    });
    for m in modules {
        let normal = match (normal, m.normal_counts) {
            (false, _) => String::new(),
            (true, Some(counts)) => format!(" {} |", counts.total()),
            (true, None) => " — |".to_string(),
        };
        out.push_str(&format!(
            "//! | [`{0}`]({0}::{0}) | `{1}` | {2} | {3} |{normal}\n",
            m.name,
            m.source_type,
            m.counts.total(),
            m.residual_counts.total()
        ));
    }
    out.push_str("\n#![forbid(unsafe_code)]\n#![deny(missing_docs)]\n\n");
    for m in sorted {
        out.push_str(&format!("#[rustfmt::skip]\npub mod {};\n", m.name));
    }
    out.push_str(
        "#[rustfmt::skip]\nmod real;\n#[rustfmt::skip]\nmod shape;\n\n\
         pub use real::Real;\n",
    );
    out.push_str(if normal {
        "pub use shape::{NormalShape, Shape};\n"
    } else {
        "pub use shape::Shape;\n"
    });
    out
}

/// The crate's own files besides the kernels' modules.
const OWN_FILES: [&str; 3] = ["lib", "real", "shape"];

/// `src/shape.rs`: the type of each kernel module's `SHAPE`, and with
/// `normal` of `NORMAL_SHAPE`.
fn shape_source(provenance: &Provenance, normal: bool) -> String {
    let mut source = format!(
        "//! The array lengths of a kernel, which `#[derive(Factor)]` compares with the\n\
         //! factor it was generated from, at compile time.\n\
         //!\n\
         //! Generated by `{}`; do not edit.\n\
         \n\
         /// The lengths of a kernel's arrays.\n\
         #[derive(Debug, Clone, Copy, PartialEq, Eq)]\n\
         pub struct Shape {{\n    \
             /// Each field's stored scalars, in declaration order.\n    \
             pub inputs: &'static [usize],\n    \
             /// The residual's length.\n    \
             pub residual: usize,\n    \
             /// Each Jacobian block's length (row-major), in variable order.\n    \
             pub blocks: &'static [usize],\n\
         }}\n",
        provenance.generate
    );
    if normal {
        source.push_str(
            "\n\
             /// The lengths of a normal-equation kernel's arrays.\n\
             #[derive(Debug, Clone, Copy, PartialEq, Eq)]\n\
             pub struct NormalShape {\n    \
                 /// Each field's stored scalars, in declaration order.\n    \
                 pub inputs: &'static [usize],\n    \
                 /// Each variable's tangent dimension, in variable order.\n    \
                 pub tangents: &'static [usize],\n    \
                 /// Each gradient block's length, in variable order.\n    \
                 pub gradient: &'static [usize],\n    \
                 /// Each Hessian block's length, pairs `a ≤ b` in the order `(0, 0), (0, 1),\n    \
                 /// …, (1, 1), …` (a diagonal block as its upper triangle).\n    \
                 pub hessian: &'static [usize],\n\
             }\n",
        );
    }
    source
}

/// A crate of generated kernels: the provenance its files name and one
/// module per kernel, ready to be written ([`GeneratedCrate::write`]) or
/// compared with the disk ([`GeneratedCrate::check`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GeneratedCrate {
    /// The generator the files name.
    pub provenance: Provenance,
    /// The kernels' modules, in the order the crate documentation lists them.
    pub modules: Vec<GeneratedModule>,
}

impl GeneratedCrate {
    /// Generates the kernel of every spec for a crate written by
    /// `provenance`'s generator.
    ///
    /// # Errors
    ///
    /// As [`generate_with`] and [`GeneratedCrate::from_modules`].
    pub fn generate(provenance: Provenance, specs: &[KernelSpec]) -> Result<Self, CodegenError> {
        let modules = specs
            .iter()
            .map(|spec| generate_with(spec, &provenance))
            .collect::<Result<Vec<_>, _>>()?;
        Self::from_modules(provenance, modules)
    }

    /// A crate of modules already generated with `provenance`.
    ///
    /// # Errors
    ///
    /// [`CodegenError::Empty`] without modules, [`CodegenError::DuplicateKernel`]
    /// for two modules of one name, [`CodegenError::ReservedName`] for a
    /// module named like one of the crate's own files (`lib`, `real`, `shape`).
    pub fn from_modules(
        provenance: Provenance,
        modules: Vec<GeneratedModule>,
    ) -> Result<Self, CodegenError> {
        if modules.is_empty() {
            return Err(CodegenError::Empty);
        }
        for (i, m) in modules.iter().enumerate() {
            if let Some(reserved) = OWN_FILES.iter().find(|own| **own == m.name) {
                return Err(CodegenError::ReservedName(reserved));
            }
            if modules[..i].iter().any(|other| other.name == m.name) {
                return Err(CodegenError::DuplicateKernel(m.name));
            }
        }
        Ok(GeneratedCrate {
            provenance,
            modules,
        })
    }

    /// Every file of `src/` as `(file name, contents)`, in a fixed order.
    pub fn files(&self) -> Vec<(String, String)> {
        let mut files = vec![
            (
                "lib.rs".to_string(),
                lib_source(&self.provenance, &self.modules),
            ),
            ("real.rs".to_string(), real_source(&self.provenance)),
            (
                "shape.rs".to_string(),
                shape_source(
                    &self.provenance,
                    self.modules.iter().any(|m| m.normal_counts.is_some()),
                ),
            ),
        ];
        for m in &self.modules {
            files.push((format!("{}.rs", m.name), m.source.clone()));
        }
        files
    }

    /// Writes the crate's sources under `dir/src` (created if missing):
    /// files whose contents differ are rewritten (each to a temporary file
    /// renamed into place), `.rs` files that are not generated are removed.
    /// Nothing outside `src/` is touched.
    ///
    /// # Errors
    ///
    /// Any I/O error.
    pub fn write(&self, dir: &Path) -> io::Result<()> {
        tree::write(&dir.join("src"), &self.files(), "rs", false)
    }

    /// Compares `dir/src` with what [`GeneratedCrate::write`] would write:
    /// `Ok` when identical, else every differing, missing or extra `.rs`
    /// file, sorted.
    pub fn check(&self, dir: &Path) -> Result<(), Vec<PathBuf>> {
        tree::check(&dir.join("src"), &self.files(), "rs", false)
    }
}
