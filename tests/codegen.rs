//! Code generation is deterministic, and the committed `generated/` (its
//! Rust `src/` and its C++ `cpp/`) is what the current factor definitions
//! generate (what `slamjac check` verifies); the C++ generation refuses
//! what C++ or Ceres cannot take.

use std::path::Path;

use factor_codegen::{CodegenError, CppLibrary, GeneratedCrate, KernelSpec, generate_module};
use factor_core::manifold::NoLocal;
use factor_core::nalgebra::Vector2;
use factor_core::{Factor, Layout, Manifold, Perturbation, Scalar, Storage};
use slamjac::kernels::{KERNEL_CRATE, PROVENANCE, shipped_kernels};

/// Regenerating from unchanged definitions is byte-identical. Two kernels
/// stand for all (every shipped kernel takes the same path; generating all
/// of them twice would cost a minute): the point's, and the plane's with
/// its branches, both with normal equations and apex's chart. The
/// committed crate, written by another process, being current (below) says
/// the same of every kernel across processes.
#[test]
fn generation_is_deterministic() {
    let specs: Vec<_> = shipped_kernels()
        .into_iter()
        .filter(|spec| ["point_reprojection", "plane"].contains(&spec.name))
        .collect();
    assert_eq!(specs.len(), 2);
    let first = GeneratedCrate::generate(PROVENANCE, &specs).expect("the kernels generate");
    let second = GeneratedCrate::generate(PROVENANCE, &specs).expect("the kernels generate");
    assert_eq!(first, second);
    assert_eq!(first.files(), second.files());
    let package = KERNEL_CRATE.package;
    let first = CppLibrary::generate(package, &PROVENANCE, &specs).expect("the C++ generates");
    let second = CppLibrary::generate(package, &PROVENANCE, &specs).expect("the C++ generates");
    assert_eq!(first, second);
}

/// The committed `generated/`, Rust and C++, is what the definitions
/// generate (what `slamjac check` verifies in CI), from one trace of each
/// kernel as `generate` makes them. On failure, run
/// `cargo run --release --no-default-features -- generate`.
#[test]
fn committed_generated_crate_is_current() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("generated");
    let specs = shipped_kernels();
    let kernels: Vec<_> = specs.iter().map(|spec| (spec.trace)()).collect();
    let modules = specs
        .iter()
        .zip(&kernels)
        .map(|(spec, kernel)| generate_module(kernel, spec, &PROVENANCE))
        .collect::<Result<Vec<_>, _>>()
        .expect("the shipped kernels generate");
    let generated = GeneratedCrate::from_modules(PROVENANCE, modules).expect("a crate");
    if let Err(stale) = generated.check(&dir) {
        panic!("stale generated files (run `slamjac generate`): {stale:?}");
    }
    let cpp = CppLibrary::from_kernels(KERNEL_CRATE.package, &PROVENANCE, &specs, &kernels)
        .expect("the shipped kernels' C++ generates");
    if let Err(stale) = cpp.check(&dir) {
        panic!("stale generated C++ (run `slamjac generate --lang cpp`): {stale:?}");
    }
}

/// An angle with an additive retraction and no `Manifold::local`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Heading<S>(S);

impl<S: Scalar> Storage<S> for Heading<S> {
    type With<T: Scalar> = Heading<T>;
    const SCALARS: usize = 1;
    fn layout() -> Layout {
        Layout::Scalar
    }
    fn map_scalars<T: Scalar>(&self, f: &mut impl FnMut(S) -> T) -> Heading<T> {
        Heading(f(self.0))
    }
    fn read_scalars(next: &mut impl FnMut() -> S) -> Self {
        Heading(next())
    }
}

impl<S: Scalar> Manifold<S> for Heading<S> {
    const DIM: usize = 1;
    fn retract(&self, delta: &[S], _side: Perturbation) -> Self {
        Heading(self.0 + delta[0])
    }
    fn tangent_description(_side: Perturbation) -> &'static str {
        "additive"
    }
}

/// `θ − θ̃`, over a heading without `local`.
#[derive(Clone, Debug, Factor)]
#[factor(residual = compass_residual, dim = 1)]
pub struct Compass<S: Scalar = f64> {
    pub measured: S,
    #[variable]
    pub heading: Heading<S>,
}

fn compass_residual<S: Scalar>(f: &Compass<S>) -> factor_core::nalgebra::Vector1<S> {
    factor_core::nalgebra::Vector1::new(f.heading.0 - f.measured)
}

/// A field named like a C++ keyword.
#[derive(Clone, Debug, Factor)]
#[factor(residual = keyword_residual, dim = 2)]
pub struct Keyword<S: Scalar = f64> {
    pub class: Vector2<S>,
    #[variable]
    pub point: Vector2<S>,
}

fn keyword_residual<S: Scalar>(f: &Keyword<S>) -> Vector2<S> {
    f.point - f.class
}

/// Ceres is refused for a variable type without `local`, naming it; the
/// factor's C++ kernel without Ceres is still generated. A field C++ cannot
/// name is refused.
#[test]
fn the_cpp_generation_refuses_what_cpp_or_ceres_cannot_take() {
    let package = KERNEL_CRATE.package;
    let error = CppLibrary::generate(
        package,
        &PROVENANCE,
        &[KernelSpec::of::<Compass>().with_ceres()],
    )
    .unwrap_err();
    assert_eq!(
        error,
        CodegenError::NoLocal {
            kernel: "compass",
            variable: "heading",
            type_name: "Heading<S>",
        }
    );
    let message = error.to_string();
    assert!(message.contains("gives no `Manifold::local`"), "{message}");
    assert!(message.contains("`MinusJacobian`"), "{message}");
    let library = CppLibrary::generate(package, &PROVENANCE, &[KernelSpec::of::<Compass>()])
        .expect("the kernel alone generates");
    let names: Vec<&str> = library
        .files
        .iter()
        .map(|(path, _)| path.as_str())
        .collect();
    assert_eq!(
        names,
        ["factor_generated/compass.h", "factor_generated/kernels.h"]
    );
    let error = CppLibrary::generate(package, &PROVENANCE, &[KernelSpec::of::<Keyword>()])
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("field `class`") && error.contains("C++ keyword"),
        "{error}"
    );
    let mut delta = [0.0];
    assert_eq!(
        Heading(1.0).local(&Heading(2.0), Perturbation::Left, &mut delta),
        Err(NoLocal)
    );
}
