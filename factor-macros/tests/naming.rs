//! The names the derive reads off its input (`src/naming.rs`), compiled
//! into this test: the crate's own unit tests would be built for the host,
//! with a second copy of its dev-dependencies (see `Cargo.toml`).

#[path = "../src/naming.rs"]
mod naming;

use naming::{snake_case, type_text};

#[test]
fn snake_case_splits_words_acronyms_and_digits() {
    assert_eq!(snake_case("PointReprojection"), "point_reprojection");
    assert_eq!(snake_case("IMUPreintegration"), "imu_preintegration");
    assert_eq!(snake_case("Se3Prior"), "se3_prior");
    assert_eq!(snake_case("Line"), "line");
    assert_eq!(snake_case("Point_To_Plane"), "point_to_plane");
}

#[test]
fn type_text_reads_like_source() {
    let ty: syn::Type = syn::parse_quote!(Se3<S>);
    assert_eq!(type_text(&ty), "Se3<S>");
    let ty: syn::Type = syn::parse_quote!(nalgebra::SMatrix<S, 3, 1>);
    assert_eq!(type_text(&ty), "nalgebra::SMatrix<S, 3, 1>");
    let ty: syn::Type = syn::parse_quote!([Vector3<S>; 2]);
    assert_eq!(type_text(&ty), "[Vector3<S>; 2]");
    let ty: syn::Type = syn::parse_quote!(<S as Trait<S>>::Out);
    assert_eq!(type_text(&ty), "<S as Trait<S>>::Out");
}
