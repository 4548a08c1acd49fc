//! The accepted forms: any scalar parameter name, a residual named by a
//! module path or `Self::`, every `#[variable]` spelling, a scalar constant,
//! `validate` and `name`. An ordinary test rather than one of trybuild's
//! pass cases (`tests/ui.rs`): with only compile-fail cases, trybuild checks
//! them all in one `cargo check` instead of building them one at a time.

use factor_core::{Factor, FactorError, Scalar};
use nalgebra::{Vector1, Vector2};

mod residuals {
    use super::*;

    pub fn spring<T: Scalar>(f: &Spring<T>) -> Vector1<T> {
        let d = f.a - f.b;
        Vector1::new(d.dot(&d) - f.rest * f.rest)
    }
}

#[derive(Clone, Debug, Factor)]
#[factor(residual = residuals::spring, dim = 1)]
#[factor(validate = spring_validate, name = "spring_2d")]
pub struct Spring<T: Scalar = f64> {
    pub rest: T,
    #[variable]
    pub a: Vector2<T>,
    #[variable(right)]
    pub b: Vector2<T>,
}

fn spring_validate(f: &Spring<f64>) -> Result<(), FactorError> {
    if f.rest < 0.0 {
        return Err(FactorError::Degenerate {
            factor: "spring_2d",
            reason: format!("negative rest length {}", f.rest),
        });
    }
    Ok(())
}

#[derive(Clone, Debug, Factor)]
#[factor(residual = Self::prior, dim = 2)]
struct Prior<S: Scalar = f64> {
    #[variable(left)]
    x: Vector2<S>,
}

impl<S: Scalar> Prior<S> {
    fn prior(&self) -> Vector2<S> {
        self.x
    }
}

#[test]
fn every_accepted_form_derives_a_factor() {
    let spring = Spring {
        rest: 1.0,
        a: Vector2::new(0.0, 0.0),
        b: Vector2::new(2.0, 0.0),
    };
    let linearization: SpringLinearization = spring.linearize().unwrap();
    assert_eq!(linearization.residual, Vector1::new(3.0));
    assert_eq!(<Spring as Factor>::NAME, "spring_2d");
    assert_eq!(Spring::TANGENT_DIM, 4);

    let prior = Prior {
        x: Vector2::new(1.0, 2.0),
    };
    let linearization: PriorLinearization = prior.linearize_dual().unwrap();
    assert_eq!(linearization.x, nalgebra::Matrix2::identity());
    assert_eq!(<Prior as Factor>::NAME, "prior");
}
