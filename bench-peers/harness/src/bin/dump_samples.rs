//! Writes a few sampled configurations of each document factor with this
//! project's `linearize_dual()` outputs as JSON, so that
//! `bench-peers/symforce_counts.py` can check that the SymForce functions it
//! counts are the same functions (conventions included).
//!
//! `cargo run --release --bin dump_samples -- OUT.json [COUNT]`

use factor_core::Factor;
use factor_core::lie::Se3;
use factor_testing::samples::Sampler;
use nalgebra::{Matrix, Storage, U1};
use serde_json::{Value, json};

fn matrix<R, C, S>(m: &Matrix<f64, R, C, S>) -> Value
where
    R: nalgebra::Dim,
    C: nalgebra::Dim,
    S: Storage<f64, R, C>,
{
    Value::from(
        (0..m.nrows())
            .map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect::<Vec<_>>())
            .collect::<Vec<_>>(),
    )
}

fn column<R: nalgebra::Dim, S: Storage<f64, R, U1>>(v: &Matrix<f64, R, U1, S>) -> Value {
    Value::from(v.iter().copied().collect::<Vec<_>>())
}

fn pose(p: &Se3<f64>) -> (Value, Value) {
    let q = p.rotation.quaternion;
    (json!([q.x, q.y, q.z, q.w]), column(&p.translation))
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let path = args.get(1).expect("usage: dump_samples OUT.json [COUNT]");
    let count: usize = args.get(2).map_or(8, |c| c.parse().expect("COUNT"));
    let mut out = serde_json::Map::new();

    let mut s = Sampler::new(1);
    let point: Vec<Value> = (0..count)
        .map(|_| {
            let f = s.point_reprojection();
            let lin = f.linearize_dual().expect("point_reprojection");
            let (rotation, translation) = pose(&f.pose);
            let k = f.intrinsics;
            json!({
                "inputs": {"rotation": rotation, "translation": translation,
                           "point": column(&f.point), "intrinsics": [k.fu, k.fv, k.cu, k.cv],
                           "observed": column(&f.observed)},
                "outputs": {"residual": matrix(&lin.residual), "d_pose": matrix(&lin.pose),
                            "d_point": matrix(&lin.point)},
            })
        })
        .collect();
    out.insert(slam_factors::PointReprojection::NAME.into(), point.into());

    let mut s = Sampler::new(2);
    let line: Vec<Value> = (0..count)
        .map(|_| {
            let f = s.line_reprojection();
            let lin = f.linearize_dual().expect("line_reprojection");
            let (rotation, translation) = pose(&f.pose);
            let (k, u) = (f.intrinsics, f.line.u.quaternion);
            json!({
                "inputs": {"rotation": rotation, "translation": translation,
                           "u": [u.x, u.y, u.z, u.w], "w": [f.line.w.cos, f.line.w.sin],
                           "intrinsics": [k.fu, k.fv, k.cu, k.cv],
                           "start": column(&f.start), "end": column(&f.end)},
                "outputs": {"residual": matrix(&lin.residual), "d_pose": matrix(&lin.pose),
                            "d_line": matrix(&lin.line)},
            })
        })
        .collect();
    out.insert(slam_factors::LineReprojection::NAME.into(), line.into());

    let mut s = Sampler::new(2);
    let plucker: Vec<Value> = (0..count)
        .map(|_| {
            let f = s.plucker_line_reprojection();
            let lin = f.linearize_dual().expect("plucker_line_reprojection");
            let (rotation, translation) = pose(&f.pose);
            let (k, n, v) = (f.intrinsics, f.line.normal, f.line.direction);
            json!({
                "inputs": {"rotation": rotation, "translation": translation,
                           "line": [n.x, n.y, n.z, v.x, v.y, v.z],
                           "intrinsics": [k.fu, k.fv, k.cu, k.cv],
                           "start": column(&f.start), "end": column(&f.end)},
                "outputs": {"residual": matrix(&lin.residual), "d_pose": matrix(&lin.pose),
                            "d_line": matrix(&lin.line)},
            })
        })
        .collect();
    out.insert(
        slam_factors::PluckerLineReprojection::NAME.into(),
        plucker.into(),
    );

    let mut s = Sampler::new(3);
    let plane: Vec<Value> = (0..count)
        .map(|_| {
            let f = s.plane();
            let lin = f.linearize_dual().expect("plane");
            let (rotation, translation) = pose(&f.pose);
            let q = f.plane.quaternion;
            json!({
                "inputs": {"rotation": rotation, "translation": translation,
                           "plane": [q.x, q.y, q.z, q.w], "measured": column(f.measured.as_ref())},
                "outputs": {"residual": matrix(&lin.residual), "d_pose": matrix(&lin.pose),
                            "d_plane": matrix(&lin.plane)},
            })
        })
        .collect();
    out.insert(slam_factors::PlaneFactor::NAME.into(), plane.into());

    std::fs::write(
        path,
        serde_json::to_string_pretty(&Value::Object(out)).expect("json"),
    )
    .expect("write samples");
    println!("wrote {count} configurations per factor to {path}");
}
