//! A user's factor's batches agree with its scalar kernel and dual numbers
//! in every lane type (`agreement::check`).

use crate::agreement::{check, sampled};

/// A user's factor (`examples/user-factor`), whose kernel crate declares the
/// `lanes` feature as the crate writer asks: poses `T_i`, `T_j` and a
/// measurement within 0.2 rad and 0.2 of the truth.
#[test]
fn a_users_relative_pose_batches_agree() {
    let factors = sampled(26, |s| {
        let (pose_i, pose_j) = (s.pose(), s.pose());
        let noise = factor_core::lie::Se3::new(s.small_rotation(0.2), s.vector3(0.2));
        user_factors::RelativePose {
            measured: noise.compose(&pose_i.inverse().compose(&pose_j)),
            pose_i,
            pose_j,
        }
    });
    check(&factors, 6, true);
}
