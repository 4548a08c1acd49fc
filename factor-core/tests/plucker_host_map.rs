//! A Plücker line served to apex-solver: through its orthonormal chart
//! (`SO3 × SO2`, 4 dof), so every value a solve can reach is on the Klein
//! quadric, with a unit direction and the moment as its normal.

use factor_core::Storage;
use factor_core::geometry::{OrthonormalLine, PluckerLine};
use factor_core::host::{Apex, ApexManifold, HostManifold, HostMap};
use nalgebra::Vector3;

/// The apex parameters of `line` (`[qw, qx, qy, qz, angle]`).
fn host_of(line: &PluckerLine<f64>) -> [f64; 5] {
    let mut host = [0.0; 5];
    PluckerLine::<f64>::host_from_stored(&line.to_scalars(), &mut host);
    host
}

/// The Plücker line whose apex parameters are `host`.
fn line_of(host: &[f64]) -> PluckerLine<f64> {
    let mut stored = [0.0; 6];
    PluckerLine::<f64>::stored_from_host(host, &mut stored);
    PluckerLine::from_scalars(&stored)
}

fn assert_on_quadric(line: &PluckerLine<f64>) {
    let (n, v) = (line.normal, line.direction);
    assert!((v.norm() - 1.0).abs() < 1e-14, "|v| = {}", v.norm());
    assert!(
        n.dot(&v).abs() < 1e-14 * n.norm().max(1.0),
        "n · v = {:e}",
        n.dot(&v)
    );
    OrthonormalLine::try_from_plucker(line).unwrap();
}

#[test]
fn a_plucker_line_is_served_as_its_orthonormal_chart() {
    let parts: Vec<ApexManifold> = <PluckerLine<f64> as HostMap<Apex>>::PARTS
        .iter()
        .map(|p| p.manifold)
        .collect();
    assert_eq!(parts, [ApexManifold::So3, ApexManifold::So2]);
    assert_eq!(parts.iter().map(|m| m.dof()).sum::<usize>(), 4);
}

/// A line written at any scale comes back as the same line, at unit
/// direction: the normal is its moment, of length its distance from the
/// origin.
#[test]
fn values_round_trip_at_unit_direction() {
    let p = Vector3::new(0.3, -1.2, 2.5);
    let q = Vector3::new(-0.7, 0.4, 3.1);
    let line = PluckerLine::from_points(&p, &q);
    for scale in [1e-3, 0.5, 1.0, 7.0, 1e4] {
        let scaled = PluckerLine::new(line.normal * scale, line.direction * scale);
        let back = line_of(&host_of(&scaled));
        assert_on_quadric(&back);
        let d = (q - p).normalize();
        assert!((back.direction - d).norm() < 1e-14, "{back:?}");
        assert!((back.normal - p.cross(&d)).norm() < 1e-14, "{back:?}");
    }
}

/// A value off the quadric (as a file may hold) is put on it: its direction
/// kept, its normal without the component along the direction (both then
/// scaled to a unit direction).
#[test]
fn values_off_the_quadric_are_projected_onto_it() {
    let skew = PluckerLine::new(Vector3::new(1.0, 2.0, 0.5), Vector3::new(0.0, 0.0, 2.0));
    let back = line_of(&host_of(&skew));
    assert_on_quadric(&back);
    assert!((back.direction - Vector3::z()).norm() < 1e-15);
    // The normal `(1, 2, 0)` orthogonal to `v`, scaled with `v` to `|v| = 1`.
    assert!(
        (back.normal - Vector3::new(0.5, 1.0, 0.0)).norm() < 1e-14,
        "{back:?}"
    );
    // A line through the origin: zero moment, the direction kept.
    let through = PluckerLine::new(Vector3::zeros(), Vector3::new(1.0, 1.0, 0.0));
    let back = line_of(&host_of(&through));
    assert!(back.normal.norm() < 1e-15, "{back:?}");
    assert!((back.direction - Vector3::new(1.0, 1.0, 0.0).normalize()).norm() < 1e-15);
}

/// Every step apex takes in the chart (its exact retraction of each part)
/// lands on the quadric: what a solve returns is a Plücker line.
#[test]
fn every_step_in_the_chart_stays_on_the_quadric() {
    let line =
        PluckerLine::from_points(&Vector3::new(1.0, 0.2, 3.0), &Vector3::new(-0.5, 1.0, 2.0));
    let host = host_of(&line);
    let steps = [
        [0.3, -0.2, 0.9, 0.4],
        [-2.0, 1.5, 0.1, -1.2],
        [0.0, 0.0, 0.0, 1.0],
    ];
    for step in steps {
        let mut moved = [0.0; 5];
        ApexManifold::So3.retract(&host[..4], &step[..3], &mut moved[..4]);
        ApexManifold::So2.retract(&host[4..], &step[3..], &mut moved[4..]);
        assert_on_quadric(&line_of(&moved));
    }
}
