//! Paths of the shipped data files.

use std::path::PathBuf;

/// The repository's `data/` folder.
pub fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../data")
        .join(name)
}

/// Every shipped file but the KITTI VO set, with its format name.
#[allow(dead_code)] // not every test file uses it
pub const SINGLE_FILES: [(&str, &str); 4] = [
    ("dubrovnik-3-7-pre.txt", "bal"),
    ("Balbianello.out", "bundler"),
    ("pose3example.txt", "g2o"),
    ("sphere2500.txt", "edge3"),
];
