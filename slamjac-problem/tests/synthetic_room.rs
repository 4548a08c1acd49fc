//! A generated room is a problem file its own reader takes: every factor
//! entry passes the problem-file checks, decodes into its factor and is
//! defined at the written values; the gauge is fixed; the counts describe
//! the file; and a request the generator cannot honour is refused.

use factor_core::Factor;
use slam_factors::{LineReprojection, PlaneFactor, PointReprojection};
use slamjac_problem::InputError;
use slamjac_problem::checks::{Shape, check, read_json};
use slamjac_problem::decode::decode;
use slamjac_problem::synthetic_room::{Kinds, RoomError, RoomRequest, generate};

fn request(seed: u64, cameras: usize, kinds: &str) -> RoomRequest {
    RoomRequest {
        seed,
        cameras,
        points: 300,
        lines: 30,
        kinds: kinds.parse().expect("kinds"),
    }
}

fn shape(factor: &str, path: &str) -> Result<Shape, InputError> {
    match factor {
        "point_reprojection" => Ok(Shape::of::<PointReprojection<f64>>()),
        "line_reprojection" => Ok(Shape::of::<LineReprojection<f64>>()),
        "plane" => Ok(Shape::of::<PlaneFactor<f64>>()),
        other => Err(InputError::new(path, format!("unexpected factor {other}"))),
    }
}

/// Decodes an entry as `F` and validates it at the written values.
fn defined<F: Factor>(entry: &slamjac_problem::checks::Entry<'_>) -> bool {
    decode::<F>(&entry.variables(), &entry.constants).is_ok_and(|f| f.validate().is_ok())
}

#[test]
fn a_generated_room_is_a_problem_file_its_reader_takes() {
    // Held-out seeds and sizes besides the default room's.
    for (seed, cameras, kinds) in [
        (0, 15, "points,lines,planes"),
        (5, 12, "points,lines,planes"),
        (11, 20, "points,lines"),
        (3, 8, "lines,planes"),
    ] {
        let room = generate(&request(seed, cameras, kinds)).expect("a room");
        let file = std::env::temp_dir().join(format!(
            "slamjac-room-{}-{seed}-{cameras}.json",
            std::process::id()
        ));
        std::fs::write(&file, room.file.to_string()).expect("written");
        let json = read_json(&file);
        std::fs::remove_file(&file).expect("removed");
        let json = json.expect("read");
        let checked = check(&json, shape).expect("checked");
        assert_eq!(checked.entries.len(), room.factors, "seed {seed}");
        assert_eq!(checked.fixed, ["c0", "c1"], "seed {seed}");
        assert!(checked.truth.is_some());
        let variables = checked.declared.iter().count();
        assert_eq!(
            variables,
            room.cameras + room.points + room.lines + room.planes,
            "seed {seed}"
        );
        for entry in &checked.entries {
            let ok = match entry.factor {
                "point_reprojection" => defined::<PointReprojection<f64>>(entry),
                "line_reprojection" => defined::<LineReprojection<f64>>(entry),
                _ => defined::<PlaneFactor<f64>>(entry),
            };
            assert!(
                ok,
                "seed {seed}: {} undefined at the written values",
                entry.path
            );
        }
    }
}

#[test]
fn the_same_seed_gives_the_same_file() {
    let a = generate(&request(4, 10, "points,lines,planes")).expect("a room");
    let b = generate(&request(4, 10, "points,lines,planes")).expect("a room");
    assert_eq!(a, b);
    let c = generate(&request(5, 10, "points,lines,planes")).expect("a room");
    assert_ne!(a.file, c.file);
}

#[test]
fn a_request_it_cannot_honour_is_refused() {
    // Three cameras cannot see a line three times with parallax.
    let lines = generate(&request(0, 3, "lines"));
    assert!(
        matches!(lines, Err(RoomError::NothingMeasured { cameras: 3, .. })),
        "{lines:?}"
    );
    // Planes alone leave the free cameras' motion along the walls free.
    let planes = generate(&request(0, 15, "planes"));
    let Err(RoomError::Unobservable(message)) = planes else {
        panic!("{planes:?}")
    };
    assert!(message.contains("is not observable"), "{message}");
    assert!("points,walls".parse::<Kinds>().is_err());
}
