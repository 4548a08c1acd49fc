//! This project's dual numbers (and generated kernels) beside Ceres 2.1's
//! Jets on the same configurations; `run.sh` drives it with `jets.cc`.
//!
//! ```text
//! jets write SAMPLES N        N configurations of each factor, in jets.cc's format
//! jets check N CERES_OUTPUT   Ceres' outputs against ours (exit 1 when they differ)
//! jets time N PASSES          ns per evaluation of each of our methods, one JSON line each
//! jets factors N PASSES       every shipped factor: dual numbers, the generated paths and the bare kernel
//! ```
//!
//! The configurations are made here from fixed seeds, so `check` and
//! `time` rebuild the very factors `write` wrote. Two residuals:
//!
//! - `SnavelyReprojection` (BAL): `Sampler::snavely_reprojection`, seed 1.
//!   Ceres parameterizes the camera by an angle-axis vector and
//!   differentiates w.r.t. it; ours is the quaternion pose in apex-solver's
//!   chart. The residual, the intrinsics' block and the point's block are
//!   the same quantities on both sides and are compared.
//! - `InverseDepthProjection` (`user-factors`, VINS-Mono's projection
//!   factor): consecutive body poses of a trajectory, seed 2. Ceres
//!   differentiates w.r.t. the poses' 7 stored parameters; its blocks
//!   times the plus-Jacobian of our chart (from [`Manifold::seeded`]) are
//!   ours, and are compared with the residual and the inverse depth's block.

use std::fmt::Write as _;
use std::hint::black_box;
use std::time::Instant;

use factor_core::lie::{Se3, Se3RhoTheta};
use factor_core::{Factor, Manifold, Perturbation, Storage};
use factor_testing::samples::Sampler;
use nalgebra::{DMatrix, Vector2};
use slam_factors::SnavelyReprojection;
use user_factors::InverseDepthProjection;

/// VINS-Mono's weight: its focal length (460 px) / 1.5 px.
const WEIGHT: f64 = 460.0 / 1.5;

fn snavely(n: usize) -> Vec<SnavelyReprojection> {
    let mut sampler = Sampler::new(1);
    (0..n).map(|_| sampler.snavely_reprojection()).collect()
}

/// A feature seen from two consecutive body poses of a trajectory (the
/// second within 0.2 rad and 0.5 m of the first) through a camera mounted
/// within 0.1 rad and 0.1 m of the body: normalized coordinates within
/// ±0.5 in camera `i`, depth 1–10 m, observed in camera `j` to within
/// 0.002 (about a pixel).
fn projection(n: usize) -> Vec<InverseDepthProjection> {
    let mut sampler = Sampler::new(2);
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let pose_i = sampler.pose();
        let step = Se3::new(sampler.small_rotation(0.2), sampler.vector3(0.5));
        let extrinsic = Se3::new(sampler.small_rotation(0.1), sampler.vector3(0.1));
        let observed_i = Vector2::new(sampler.uniform(-0.5, 0.5), sampler.uniform(-0.5, 0.5));
        let mut factor = InverseDepthProjection {
            observed_i,
            observed_j: Vector2::zeros(),
            weight: WEIGHT,
            pose_i: Se3RhoTheta::new(pose_i),
            pose_j: Se3RhoTheta::new(pose_i.compose(&step)),
            extrinsic: Se3RhoTheta::new(extrinsic),
            inverse_depth: 1.0 / sampler.uniform(1.0, 10.0),
        };
        let noise = Vector2::new(
            sampler.uniform(-0.002, 0.002),
            sampler.uniform(-0.002, 0.002),
        );
        // The residual at observed_j = 0 is the prediction times the weight.
        match factor.residual() {
            Ok(prediction) => factor.observed_j = prediction / WEIGHT + noise,
            Err(_) => continue,
        }
        if factor.validate().is_ok() {
            out.push(factor);
        }
    }
    out
}

/// `[p, q]` with `q = [x, y, z, w]`: how Ceres' side (and VINS-Mono) store a pose.
fn pose_text(pose: &Se3RhoTheta<f64>, out: &mut String) {
    let (t, q) = (pose.translation(), pose.se3().rotation.quaternion);
    for v in [t.x, t.y, t.z, q.x, q.y, q.z, q.w] {
        write!(out, " {v:e}").unwrap();
    }
}

fn write(path: &str, n: usize) {
    let mut out = format!("snavely {n}\n");
    for f in snavely(n) {
        let pose = f.pose.se3();
        let angle_axis = pose.rotation.log();
        let t = pose.translation;
        let k = f.intrinsics;
        let values = [
            angle_axis.x,
            angle_axis.y,
            angle_axis.z,
            t.x,
            t.y,
            t.z,
            k.focal,
            k.k1,
            k.k2,
            f.point.x,
            f.point.y,
            f.point.z,
            f.observed.x,
            f.observed.y,
        ];
        for v in values {
            write!(out, " {v:e}").unwrap();
        }
        out.push('\n');
    }
    writeln!(out, "projection {n}").unwrap();
    for f in projection(n) {
        for pose in [&f.pose_i, &f.pose_j, &f.extrinsic] {
            pose_text(pose, &mut out);
        }
        let values = [
            f.inverse_depth,
            f.observed_i.x,
            f.observed_i.y,
            f.observed_j.x,
            f.observed_j.y,
            f.weight,
        ];
        for v in values {
            write!(out, " {v:e}").unwrap();
        }
        out.push('\n');
    }
    std::fs::write(path, out).unwrap_or_else(|e| fail(&format!("{path}: {e}")));
}

fn fail(message: &str) -> ! {
    eprintln!("error: {message}");
    std::process::exit(2);
}

/// `max |a − b| / max |b|` (at least 1e-300).
fn relative(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    (a - b).amax() / b.amax().max(1e-300)
}

/// Ceres' ambient block of a pose (rows × `[p, q]`, row-major) in our chart:
/// times the plus-Jacobian `∂ stored(x ⊞ δ)/∂δ` of `Se3RhoTheta` on the right.
fn in_our_chart(ambient: &[f64], pose: &Se3RhoTheta<f64>) -> DMatrix<f64> {
    let plus = Manifold::<f64>::seeded::<6, 6>(pose, Perturbation::Right, 0);
    let mut stored = Vec::new();
    plus.map_scalars(&mut |s| {
        stored.push(s);
        s
    });
    // Stored [qx, qy, qz, qw, x, y, z]; Ceres' columns [px, py, pz, qx, qy, qz, qw].
    let ceres_column = |i: usize| if i < 4 { 3 + i } else { i - 4 };
    DMatrix::from_fn(2, 6, |r, c| {
        (0..7)
            .map(|i| ambient[7 * r + ceres_column(i)] * stored[i].eps[c])
            .sum()
    })
}

fn check(n: usize, ceres: &str) {
    let text = std::fs::read_to_string(ceres).unwrap_or_else(|e| fail(&format!("{ceres}: {e}")));
    let lines: Vec<Vec<f64>> = text
        .lines()
        .map(|l| {
            l.split_whitespace()
                .skip(1)
                .map(|v| v.parse().unwrap())
                .collect()
        })
        .collect();
    let (snavely_lines, projection_lines) = lines.split_at(n);
    let mut worst = 0.0_f64;
    for (f, c) in snavely(n).iter().zip(snavely_lines) {
        let ours = f
            .linearize_dual()
            .unwrap_or_else(|e| fail(&e.to_string()))
            .to_dyn();
        let residual = DMatrix::from_column_slice(2, 1, ours.residual.as_slice());
        let camera = DMatrix::from_row_slice(2, 9, &c[2..20]);
        let pairs = [
            (DMatrix::from_column_slice(2, 1, &c[..2]), residual),
            (camera.columns(6, 3).into_owned(), ours.jacobians[1].clone()),
            (
                DMatrix::from_row_slice(2, 3, &c[20..26]),
                ours.jacobians[2].clone(),
            ),
        ];
        for (theirs, ours) in pairs {
            worst = worst.max(relative(&theirs, &ours));
        }
    }
    for (f, c) in projection(n).iter().zip(projection_lines) {
        let ours = f
            .linearize_dual()
            .unwrap_or_else(|e| fail(&e.to_string()))
            .to_dyn();
        let [pose_i, pose_j, extrinsic, inverse_depth] = &ours.jacobians[..] else {
            fail("four Jacobian blocks");
        };
        let pairs = [
            (
                DMatrix::from_column_slice(2, 1, &c[..2]),
                DMatrix::from_column_slice(2, 1, ours.residual.as_slice()),
            ),
            (in_our_chart(&c[2..16], &f.pose_i), pose_i.clone()),
            (in_our_chart(&c[16..30], &f.pose_j), pose_j.clone()),
            (in_our_chart(&c[30..44], &f.extrinsic), extrinsic.clone()),
            (
                DMatrix::from_column_slice(2, 1, &c[44..46]),
                inverse_depth.clone(),
            ),
        ];
        for (theirs, ours) in pairs {
            worst = worst.max(relative(&theirs, &ours));
        }
    }
    println!("largest relative difference from Ceres' Jets: {worst:.2e}");
    if !(worst <= 1e-9) {
        fail("Ceres' outputs differ from ours beyond 1e-9");
    }
}

/// Min and median ns per evaluation over `passes` passes of `pass`.
///
/// With `JETS_ONLY=FACTOR/METHOD` in the environment, only that one is timed
/// (for a profiler).
fn time(factor: &str, method: &str, n: usize, passes: usize, mut pass: impl FnMut() -> f64) {
    if std::env::var("JETS_ONLY").is_ok_and(|only| only != format!("{factor}/{method}")) {
        return;
    }
    let mut ns = Vec::with_capacity(passes);
    let mut sink = 0.0;
    for _ in 0..passes {
        let start = Instant::now();
        sink += pass();
        ns.push(start.elapsed().as_nanos() as f64 / n as f64);
    }
    ns.sort_by(f64::total_cmp);
    println!(
        "{{\"factor\": \"{factor}\", \"method\": \"{method}\", \"min_ns\": {:.2}, \
         \"median_ns\": {:.2}, \"sink\": {sink:.3e}}}",
        ns[0],
        ns[passes / 2]
    );
}

/// The stored scalars of each field of `f`, for the bare kernels.
fn fields<F: Factor>(f: &F) -> Vec<Vec<f64>> {
    let stored = f.to_scalars();
    let mut rest = stored.as_slice();
    F::fields()
        .iter()
        .map(|field| {
            let (head, tail) = rest.split_at(field.scalars);
            rest = tail;
            head.to_vec()
        })
        .collect()
}

fn array<const N: usize>(values: &[f64]) -> [f64; N] {
    values.try_into().expect("the kernel's input length")
}

fn time_snavely(n: usize, passes: usize) {
    let factors = snavely(n);
    let stored: Vec<Vec<f64>> = factors.iter().map(|f| f.to_scalars()).collect();
    type Inputs = ([f64; 2], [f64; 7], [f64; 3], [f64; 3]);
    let inputs: Vec<Inputs> = factors
        .iter()
        .map(|f| {
            let v = fields(f);
            (array(&v[0]), array(&v[1]), array(&v[2]), array(&v[3]))
        })
        .collect();
    let name = "snavely";
    time(name, "dual", n, passes, || {
        factors
            .iter()
            .map(|f| {
                black_box(f)
                    .linearize_dual()
                    .map_or(0.0, |l| l.residual[0] + l.pose[0])
            })
            .sum()
    });
    time(name, "generated", n, passes, || {
        factors
            .iter()
            .map(|f| {
                black_box(f)
                    .linearize_generated()
                    .map_or(0.0, |l| l.residual[0] + l.pose[0])
            })
            .sum()
    });
    time(name, "linearize_stored_into", n, passes, || {
        let (mut r, mut a, mut b, mut c) = ([0.0; 2], [0.0; 12], [0.0; 6], [0.0; 6]);
        let mut sum = 0.0;
        for s in &stored {
            let blocks = &mut [Some(&mut a[..]), Some(&mut b[..]), Some(&mut c[..])];
            if SnavelyReprojection::linearize_stored_into(black_box(s), &mut r, blocks).is_ok() {
                black_box((&r, &a, &b, &c));
                sum += r[0] + a[0];
            }
        }
        sum
    });
    time(name, "linearize_stored_validated_into", n, passes, || {
        let (mut r, mut a, mut b, mut c) = ([0.0; 2], [0.0; 12], [0.0; 6], [0.0; 6]);
        let mut sum = 0.0;
        for s in &stored {
            let blocks = &mut [Some(&mut a[..]), Some(&mut b[..]), Some(&mut c[..])];
            if SnavelyReprojection::linearize_stored_validated_into(black_box(s), &mut r, blocks)
                .is_ok()
            {
                black_box((&r, &a, &b, &c));
                sum += r[0] + a[0];
            }
        }
        sum
    });
    // The pose's block alone, the others held fixed (pose tracking's path).
    time(name, "linearize_stored_into_pose", n, passes, || {
        let (mut r, mut a) = ([0.0; 2], [0.0; 12]);
        let mut sum = 0.0;
        for s in &stored {
            let blocks = &mut [Some(&mut a[..]), None, None];
            if SnavelyReprojection::linearize_stored_into(black_box(s), &mut r, blocks).is_ok() {
                black_box((&r, &a));
                sum += r[0] + a[0];
            }
        }
        sum
    });
    time(name, "kernel_slices", n, passes, || {
        let (mut r, mut a, mut b, mut c) = ([0.0; 2], [0.0; 12], [0.0; 6], [0.0; 6]);
        let mut sum = 0.0;
        for (o, p, k, x) in &inputs {
            let ins: [&[f64]; 4] = [o, p, k, x];
            let mut blocks = [Some(&mut a[..]), Some(&mut b[..]), Some(&mut c[..])];
            factor_generated::snavely_reprojection::snavely_reprojection_slices(
                black_box(&ins),
                &mut r,
                &mut blocks,
            );
            black_box((&r, &blocks));
            sum += r[0];
        }
        sum
    });
    time(name, "validate", n, passes, || {
        factors
            .iter()
            .map(|f| f64::from(u8::from(black_box(f).validate().is_ok())))
            .sum()
    });
    time(name, "kernel", n, passes, || {
        let (mut r, mut a, mut b, mut c) = ([0.0; 2], [0.0; 12], [0.0; 6], [0.0; 6]);
        let mut sum = 0.0;
        for (o, p, k, x) in &inputs {
            factor_generated::snavely_reprojection::snavely_reprojection(
                black_box(o),
                black_box(p),
                black_box(k),
                black_box(x),
                &mut r,
                Some(&mut a),
                Some(&mut b),
                Some(&mut c),
            );
            // Every output used, so that none is optimized away.
            black_box((&r, &a, &b, &c));
            sum += r[0] + a[0];
        }
        sum
    });
}

fn time_projection(n: usize, passes: usize) {
    let factors = projection(n);
    type Inputs = (
        [f64; 2],
        [f64; 2],
        [f64; 1],
        [f64; 7],
        [f64; 7],
        [f64; 7],
        [f64; 1],
    );
    let inputs: Vec<Inputs> = factors
        .iter()
        .map(|f| {
            let v = fields(f);
            let a = |k: usize| array::<7>(&v[k]);
            (
                array(&v[0]),
                array(&v[1]),
                array(&v[2]),
                a(3),
                a(4),
                a(5),
                array(&v[6]),
            )
        })
        .collect();
    let name = "projection";
    time(name, "dual", n, passes, || {
        factors
            .iter()
            .map(|f| {
                black_box(f)
                    .linearize_dual()
                    .map_or(0.0, |l| l.residual[0] + l.pose_i[0])
            })
            .sum()
    });
    time(name, "generated", n, passes, || {
        factors
            .iter()
            .map(|f| black_box(black_box(f).linearize_generated()).map_or(0.0, |l| l.residual[0]))
            .sum()
    });
    time(name, "kernel", n, passes, || {
        let mut r = [0.0; 2];
        let (mut a, mut b, mut c, mut d) = ([0.0; 12], [0.0; 12], [0.0; 12], [0.0; 2]);
        let mut sum = 0.0;
        for (oi, oj, w, pi, pj, e, l) in &inputs {
            user_kernels::inverse_depth_projection::inverse_depth_projection(
                black_box(oi),
                black_box(oj),
                black_box(w),
                black_box(pi),
                black_box(pj),
                black_box(e),
                black_box(l),
                &mut r,
                Some(&mut a),
                Some(&mut b),
                Some(&mut c),
                Some(&mut d),
            );
            black_box((&r, &a, &b, &c, &d));
            sum += r[0] + a[0];
        }
        sum
    });
}

/// A kernel's slice entry (`<factor>_slices` of `factor-generated`).
type Slices = fn(&[&[f64]], &mut [f64], &mut [Option<&mut [f64]>]) -> bool;

/// One factor type's paths on `factors`, every block requested and every
/// output kept: `linearize_dual_into` (dual numbers), `linearize_into` and
/// `linearize_stored_into` (the generated kernel), which validate and check
/// finiteness, `linearize_stored_validated_into` (the same without the
/// validation), and the bare kernel through its slice entry, out of line.
fn time_factor<F: Factor>(name: &str, factors: &[F], passes: usize, kernel: Slices) {
    let n = factors.len();
    let rows = F::RESIDUAL_DIM;
    let mut residual = vec![0.0; rows];
    let mut blocks: Vec<Vec<f64>> = F::variables()
        .iter()
        .map(|v| vec![0.0; rows * v.tangent_dim])
        .collect();
    let mut out: Vec<Option<&mut [f64]>> = blocks.iter_mut().map(|b| Some(&mut b[..])).collect();
    time(name, "dual", n, passes, || {
        let mut sum = 0.0;
        for f in factors {
            if black_box(f)
                .linearize_dual_into(&mut residual, &mut out)
                .is_ok()
            {
                black_box((&residual, &out));
                sum += residual[0];
            }
        }
        sum
    });
    time(name, "generated", n, passes, || {
        let mut sum = 0.0;
        for f in factors {
            if black_box(f).linearize_into(&mut residual, &mut out).is_ok() {
                black_box((&residual, &out));
                sum += residual[0];
            }
        }
        sum
    });
    let scalars: Vec<Vec<f64>> = factors.iter().map(Storage::to_scalars).collect();
    time(name, "stored", n, passes, || {
        let mut sum = 0.0;
        for s in &scalars {
            if F::linearize_stored_into(black_box(s), &mut residual, &mut out).is_ok() {
                black_box((&residual, &out));
                sum += residual[0];
            }
        }
        sum
    });
    time(name, "stored_validated", n, passes, || {
        let mut sum = 0.0;
        for s in &scalars {
            if F::linearize_stored_validated_into(black_box(s), &mut residual, &mut out).is_ok() {
                black_box((&residual, &out));
                sum += residual[0];
            }
        }
        sum
    });
    let stored: Vec<Vec<Vec<f64>>> = factors.iter().map(fields).collect();
    let inputs: Vec<Vec<&[f64]>> = stored
        .iter()
        .map(|v| v.iter().map(Vec::as_slice).collect())
        .collect();
    // Called out of line (the pointer hidden from the optimizer), so that
    // the slice entry is not inlined into this loop for some factors only.
    let kernel = black_box(kernel);
    time(name, "kernel", n, passes, || {
        let mut sum = 0.0;
        for i in &inputs {
            kernel(black_box(i), &mut residual, &mut out);
            black_box((&residual, &out));
            sum += residual[0];
        }
        sum
    });
}

/// Every shipped factor with a sampler, `n` configurations each (seed 7).
fn time_factors(n: usize, passes: usize) {
    use factor_generated as g;
    fn sampled<F>(n: usize, sample: impl Fn(&mut Sampler) -> F) -> Vec<F> {
        let mut sampler = Sampler::new(7);
        (0..n).map(|_| sample(&mut sampler)).collect()
    }
    time_factor(
        "point_reprojection",
        &sampled(n, Sampler::point_reprojection),
        passes,
        g::point_reprojection::point_reprojection_slices,
    );
    time_factor(
        "line_reprojection",
        &sampled(n, Sampler::line_reprojection),
        passes,
        g::line_reprojection::line_reprojection_slices,
    );
    time_factor(
        "plucker_line_reprojection",
        &sampled(n, Sampler::plucker_line_reprojection),
        passes,
        g::plucker_line_reprojection::plucker_line_reprojection_slices,
    );
    time_factor(
        "plane",
        &sampled(n, Sampler::plane),
        passes,
        g::plane::plane_slices,
    );
    time_factor(
        "free_line",
        &sampled(n, Sampler::free_line),
        passes,
        g::free_line::free_line_slices,
    );
    time_factor(
        "snavely_reprojection",
        &sampled(n, Sampler::snavely_reprojection),
        passes,
        g::snavely_reprojection::snavely_reprojection_slices,
    );
    time_factor(
        "stereo_reprojection",
        &sampled(n, Sampler::stereo_reprojection),
        passes,
        g::stereo_reprojection::stereo_reprojection_slices,
    );
    time_factor(
        "between",
        &sampled(n, Sampler::between),
        passes,
        g::between::between_slices,
    );
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let number = |i: usize| -> usize {
        args.get(i)
            .and_then(|s| s.parse().ok())
            .filter(|&n| n > 0)
            .unwrap_or_else(|| fail("expected a positive number"))
    };
    match args.first().map(String::as_str) {
        Some("write") if args.len() == 3 => write(&args[1], number(2)),
        Some("check") if args.len() == 3 => check(number(1), &args[2]),
        Some("factors") if args.len() == 3 => time_factors(number(1), number(2)),
        Some("time") if args.len() == 3 => {
            time_snavely(number(1), number(2));
            time_projection(number(1), number(2));
        }
        _ => fail(
            "usage: jets write SAMPLES N | jets check N CERES_OUTPUT | jets time N PASSES | \
             jets factors N PASSES",
        ),
    }
}
