//! Geometry of the documents' landmarks and measurements, generic over the scalar.

pub mod bearing;
pub mod camera;
pub mod free_line;
pub mod orthonormal_line;
pub mod plane;
pub mod plucker;

pub use bearing::bearing_plane_normal;
pub use camera::Intrinsics;
pub use free_line::FreeLine;
pub use orthonormal_line::OrthonormalLine;
pub use plane::InfinitePlane;
pub use plucker::PluckerLine;
