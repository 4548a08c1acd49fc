//! The similarity that best maps one point set onto another in the least
//! squares sense (Umeyama 1991, "Least-squares estimation of transformation
//! parameters between two point patterns"): the alignment of an estimated
//! trajectory to the truth before its error is measured, with the scale
//! (Sim(3)) or without (SE(3)).

use nalgebra::{Matrix3, Rotation3, Similarity3, Translation3, UnitQuaternion, Vector3};

/// The similarity `x ↦ s R x + t` minimising `Σ |to_i − (s R from_i + t)|²`,
/// `s = 1` unless `scale`; `None` for fewer than 3 pairs, or point sets
/// whose spread is zero.
///
/// With `Σ = (1/n) Σ (to_i − μ_to)(from_i − μ_from)ᵀ = U D Vᵀ`: `R = U S Vᵀ`,
/// `S = diag(1, 1, det(U) det(V))` (a rotation, never a reflection),
/// `s = tr(D S) / σ²_from`, `t = μ_to − s R μ_from`.
pub fn umeyama(
    from: &[Vector3<f64>],
    to: &[Vector3<f64>],
    scale: bool,
) -> Option<Similarity3<f64>> {
    let n = from.len();
    if n < 3 || to.len() != n {
        return None;
    }
    let mean = |v: &[Vector3<f64>]| v.iter().sum::<Vector3<f64>>() / n as f64;
    let (mu_from, mu_to) = (mean(from), mean(to));
    let variance = from
        .iter()
        .map(|x| (x - mu_from).norm_squared())
        .sum::<f64>()
        / n as f64;
    // Zero, or NaN from non-finite points.
    if variance.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let covariance = from
        .iter()
        .zip(to)
        .map(|(x, y)| (y - mu_to) * (x - mu_from).transpose())
        .sum::<Matrix3<f64>>()
        / n as f64;
    let svd = covariance.svd(true, true);
    let (u, v_t) = (svd.u?, svd.v_t?);
    let mut s = Vector3::new(1.0, 1.0, 1.0);
    if u.determinant() * v_t.determinant() < 0.0 {
        s.z = -1.0;
    }
    let rotation = u * Matrix3::from_diagonal(&s) * v_t;
    let factor = if scale {
        svd.singular_values.dot(&s) / variance
    } else {
        1.0
    };
    let translation = mu_to - factor * rotation * mu_from;
    Some(Similarity3::from_parts(
        Translation3::from(translation),
        UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(rotation)),
        factor,
    ))
}

#[cfg(test)]
mod tests {
    use nalgebra::Point3;

    use super::*;

    /// Points not on a plane, mapped by a known similarity, give it back.
    #[test]
    fn a_known_similarity_is_recovered() {
        let from: Vec<Vector3<f64>> = (0..10)
            .map(|i| {
                let t = f64::from(i);
                Vector3::new(t.sin() * 3.0, (0.7 * t).cos() * 2.0, 0.1 * t * t - 1.0)
            })
            .collect();
        let rotation = UnitQuaternion::from_scaled_axis(Vector3::new(0.3, -1.2, 2.0));
        let translation = Vector3::new(1.5, -4.0, 0.25);
        for scale in [1.0, 2.5] {
            let to: Vec<Vector3<f64>> = from
                .iter()
                .map(|x| scale * (rotation * x) + translation)
                .collect();
            let found = umeyama(&from, &to, scale != 1.0).unwrap();
            assert!((found.scaling() - scale).abs() < 1e-12, "{found}");
            assert!(found.isometry.rotation.angle_to(&rotation) < 1e-12);
            assert!((found.isometry.translation.vector - translation).norm() < 1e-12);
            for (x, y) in from.iter().zip(&to) {
                assert!((found * Point3::from(*x) - Point3::from(*y)).norm() < 1e-12);
            }
        }
        // Without the scale, a scaled set is aligned by rotation and
        // translation only.
        let doubled: Vec<Vector3<f64>> = from.iter().map(|x| 2.0 * x).collect();
        assert_eq!(umeyama(&from, &doubled, false).unwrap().scaling(), 1.0);
        assert!(umeyama(&from[..2], &doubled[..2], true).is_none());
    }
}
