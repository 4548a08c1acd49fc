//! The file formats, by name and by detection.

use std::fmt;
use std::io::BufRead;
use std::path::Path;
use std::str::FromStr;

use slamjac_io::replay::{self, Replayed};

use crate::bundler::HEADER as BUNDLER_HEADER;
use crate::error::Error;
use crate::input::{self, Lines, parse_integer};

/// A data-set format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Format {
    /// Bundle Adjustment in the Large ([`crate::bal`]).
    Bal,
    /// Bundler v0.3 ([`crate::bundler`]).
    Bundler,
    /// g2o `VERTEX_SE3:QUAT`/`EDGE_SE3:QUAT` ([`crate::g2o`]).
    G2o,
    /// g2o's 3D lines, planes and points beside the poses
    /// (`types_slam3d_addons`: `VERTEX_LINE3D`, `VERTEX_PLANE`,
    /// `EDGE_SE3_LINE3D`, `EDGE_SE3_PLANE_CALIB`; `types_slam3d`:
    /// `VERTEX_TRACKXYZ`, `EDGE_SE3_TRACKXYZ`, `EDGE_SE3_PRIOR`,
    /// `PARAMS_SE3OFFSET`; `FIX`; [`crate::g2o::read_graph`]). A pose graph
    /// with a prior is one.
    G2oAddons,
    /// `VERTEX3`/`EDGE3` ([`crate::edge3`]).
    Edge3,
    /// GTSAM's KITTI stereo VO files ([`crate::kitti_vo`]).
    KittiVo,
}

impl Format {
    /// Every format, in the order of their names in messages.
    pub const ALL: [Format; 6] = [
        Format::Bal,
        Format::Bundler,
        Format::G2o,
        Format::G2oAddons,
        Format::Edge3,
        Format::KittiVo,
    ];

    /// The name [`FromStr`] takes: `bal`, `bundler`, `g2o`, `g2o-addons`,
    /// `edge3`, `kitti-vo`.
    pub fn name(self) -> &'static str {
        match self {
            Format::Bal => "bal",
            Format::Bundler => "bundler",
            Format::G2o => "g2o",
            Format::G2oAddons => "g2o-addons",
            Format::Edge3 => "edge3",
            Format::KittiVo => "kitti-vo",
        }
    }

    /// The format a file's name tells: `VO_*.txt` is KITTI VO, `*.out`
    /// Bundler; `None` for any other name (`.txt` is ambiguous, and `.g2o`
    /// a pose graph or one with lines and planes: see
    /// [`Format::from_content`]).
    pub fn from_name(path: &Path) -> Option<Format> {
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or_default();
        if name.starts_with("VO_") && name.ends_with(".txt") {
            return Some(Format::KittiVo);
        }
        match path.extension().and_then(|e| e.to_str()) {
            Some("out") => Some(Format::Bundler),
            // `.g2o` is a pose graph or one with lines and planes: the
            // content tells which.
            _ => None,
        }
    }

    /// The format the start of an input tells (at most [`SNIFF_BYTES`] of
    /// it are looked at): a first line `# Bundle file v0.3` is Bundler, and
    /// the first record (skipping blank and `#` lines) starting with
    /// `VERTEX_SE3:QUAT`/`EDGE_SE3:QUAT` is g2o (with lines and planes,
    /// [`Format::G2oAddons`], when a record within the window starts with a
    /// tag only those have, or the first does), with `VERTEX3`/`EDGE3`
    /// EDGE3, and of three integers BAL. `name` names the input in errors.
    /// [`crate::Problem::read_from`] sniffs a stream this way and reads it
    /// once.
    pub fn from_content(reader: impl BufRead, name: &str) -> Result<Format, Error> {
        let mut lines = Lines::new(reader, name);
        if let Some(first) = lines.next_line()?
            && first.text.trim_end() == BUNDLER_HEADER
        {
            return Ok(Format::Bundler);
        }
        // The first line is read: look at it unless it is blank or a comment.
        let first_is_record = {
            let text = lines.current_text();
            text.split_ascii_whitespace()
                .next()
                .is_some_and(|t| !t.starts_with('#'))
        };
        if !first_is_record && lines.next_record()?.is_none() {
            return Err(lines.error(format!(
                "no record in the first {} to tell the format from; give it with --format ({})",
                sniff_limit(),
                names()
            )));
        }
        let record: Vec<String> = lines
            .current_text()
            .split_ascii_whitespace()
            .map(str::to_owned)
            .collect();
        let fields: Vec<&str> = record.iter().map(String::as_str).collect();
        match fields.as_slice() {
            ["VERTEX_SE3:QUAT" | "EDGE_SE3:QUAT", ..] => Ok(g2o_dialect(&mut lines)),
            [tag, ..] if ADDON_TAGS.contains(tag) => Ok(Format::G2oAddons),
            ["VERTEX3" | "EDGE3", ..] => Ok(Format::Edge3),
            [a, b, c] if [a, b, c].iter().all(|t| parse_integer(t).is_ok()) => Ok(Format::Bal),
            _ => Err(lines.error(format!(
                "cannot tell the format from this line; give it with --format ({})",
                names()
            ))),
        }
    }

    /// The format of the file at `path`: from its name, else from its
    /// content ([`Format::from_name`], [`Format::from_content`]).
    pub fn detect(path: &Path) -> Result<Format, Error> {
        if let Some(format) = Format::from_name(path) {
            return Ok(format);
        }
        let (reader, name) = input::open(path)?;
        sniff(reader, &name).0
    }
}

/// At most this much of an input is read to tell its format from its
/// content (1 MiB): an input whose first record lies further needs its
/// format given.
pub const SNIFF_BYTES: usize = 1 << 20;

/// [`SNIFF_BYTES`] in words.
fn sniff_limit() -> String {
    format!("{} MiB", SNIFF_BYTES >> 20)
}

/// The format `reader`'s content tells, and the whole input from its first
/// byte: what was read to tell the format is replayed in front of the rest,
/// so the input is read once (a pipe cannot be read twice).
pub(crate) fn sniff<R: BufRead>(reader: R, name: &str) -> (Result<Format, Error>, Replayed<R>) {
    replay::sniff(reader, SNIFF_BYTES, |start| {
        Format::from_content(start, name)
    })
}

/// The record tags of g2o's graphs that its plain pose graphs
/// (`VERTEX_SE3:QUAT`, `EDGE_SE3:QUAT` only) do not have.
const ADDON_TAGS: [&str; 9] = [
    "PARAMS_SE3OFFSET",
    "VERTEX_LINE3D",
    "VERTEX_PLANE",
    "VERTEX_TRACKXYZ",
    "EDGE_SE3_LINE3D",
    "EDGE_SE3_PLANE_CALIB",
    "EDGE_SE3_TRACKXYZ",
    "EDGE_SE3_PRIOR",
    "FIX",
];

/// [`Format::G2oAddons`] when a record of the g2o input from `lines` on
/// (within what the format is told from, [`SNIFF_BYTES`]) starts with one of
/// [`ADDON_TAGS`], [`Format::G2o`] otherwise. The window may end inside a
/// record: what cannot be read there ends the search.
fn g2o_dialect<R: BufRead>(lines: &mut Lines<R>) -> Format {
    while let Ok(Some(_)) = lines.next_record() {
        let tag = lines.current_text().split_ascii_whitespace().next();
        if tag.is_some_and(|t| ADDON_TAGS.contains(&t)) {
            return Format::G2oAddons;
        }
    }
    Format::G2o
}

/// The format names, for messages.
fn names() -> String {
    Format::ALL.map(Format::name).join(", ")
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A name that is not a format.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown format `{0}` (one of {names})", names = names())]
pub struct UnknownFormat(pub String);

impl FromStr for Format {
    type Err = UnknownFormat;

    fn from_str(name: &str) -> Result<Self, Self::Err> {
        Format::ALL
            .into_iter()
            .find(|f| f.name() == name)
            .ok_or_else(|| UnknownFormat(name.to_owned()))
    }
}
