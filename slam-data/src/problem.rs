//! A problem of any format: read by path with the format detected or
//! given, written back in its format.

use std::path::Path;

use crate::bal::{self, BalProblem};
use crate::bundler::{self, BundlerProblem};
use crate::edge3;
use crate::error::Error;
use crate::format::Format;
use crate::g2o;
use crate::g2o_graph::G2oGraph;
use crate::kitti_vo::{self, StereoVo, VoFiles};
use crate::pose_graph::PoseGraph;

/// A problem read from a file, tagged with its format.
#[derive(Debug, Clone, PartialEq)]
pub enum Problem {
    /// A BAL bundle-adjustment problem.
    Bal(BalProblem),
    /// A Bundler reconstruction.
    Bundler(BundlerProblem),
    /// A g2o pose graph.
    G2o(PoseGraph),
    /// A g2o graph with 3D lines and planes.
    G2oAddons(G2oGraph),
    /// An EDGE3 pose graph.
    Edge3(PoseGraph),
    /// A KITTI stereo VO problem.
    KittiVo(StereoVo),
}

impl Problem {
    /// Reads the problem at `path`, in `format` or else the one
    /// [detected](Format::detect). A KITTI VO problem is named by any of its
    /// three files ([`VoFiles::beside`]).
    pub fn read(path: impl AsRef<Path>, format: Option<Format>) -> Result<Problem, Error> {
        let path = path.as_ref();
        let format = match format {
            Some(format) => format,
            None => Format::detect(path)?,
        };
        Ok(match format {
            Format::Bal => Problem::Bal(bal::read(path)?),
            Format::Bundler => Problem::Bundler(bundler::read(path)?),
            Format::G2o => Problem::G2o(g2o::read(path)?),
            Format::G2oAddons => Problem::G2oAddons(g2o::read_graph(path)?),
            Format::Edge3 => Problem::Edge3(edge3::read(path)?),
            Format::KittiVo => Problem::KittiVo(kitti_vo::read(&VoFiles::beside(path)?)?),
        })
    }

    /// The problem's format.
    pub fn format(&self) -> Format {
        match self {
            Problem::Bal(_) => Format::Bal,
            Problem::Bundler(_) => Format::Bundler,
            Problem::G2o(_) => Format::G2o,
            Problem::G2oAddons(_) => Format::G2oAddons,
            Problem::Edge3(_) => Format::Edge3,
            Problem::KittiVo(_) => Format::KittiVo,
        }
    }

    /// Writes the problem at `path` in its format (a KITTI VO problem to the
    /// three files [`VoFiles::beside`] names).
    pub fn write(&self, path: impl AsRef<Path>) -> Result<(), Error> {
        let path = path.as_ref();
        match self {
            Problem::Bal(problem) => bal::write(problem, path),
            Problem::Bundler(problem) => bundler::write(problem, path),
            Problem::G2o(graph) => g2o::write(graph, path),
            Problem::G2oAddons(graph) => g2o::write_graph(graph, path),
            Problem::Edge3(graph) => edge3::write(graph, path),
            Problem::KittiVo(vo) => kitti_vo::write(vo, &VoFiles::beside(path)?),
        }
    }
}
