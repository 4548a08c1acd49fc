//! The shipped factors in apex-solver's chart (`factor_core::host::Apex`):
//! dual numbers through the host trace against central differences through
//! the description's exact retraction.

use factor_core::host::{Apex, HostFactor, HostManifold};
use factor_testing::host::{HostCheck, check_host_dual};
use factor_testing::samples::Sampler;

fn check<F: HostFactor<Apex>>(factor: &F) -> HostCheck {
    check_host_dual::<F, Apex>(factor, 1e-4, |m, p, d, out| m.retract(p, d, out))
        .unwrap_or_else(|e| panic!("{}: {e}", F::NAME))
}

#[test]
fn document_factors_in_apex_chart_match_central_differences() {
    let mut sampler = Sampler::new(7);
    for _ in 0..50 {
        let checks = [
            check(&sampler.point_reprojection()),
            check(&sampler.line_reprojection()),
            check(&sampler.plane()),
            check(&sampler.free_line()),
            check(&sampler.plucker_line_reprojection()),
            check(&sampler.snavely_reprojection()),
            check(&sampler.stereo_reprojection()),
            check(&sampler.between()),
        ];
        for c in checks {
            assert!(c.max_error() < 1e-7, "{c:?}");
        }
    }
}

/// The generated apex kernels against central differences through the
/// description's exact retraction.
#[test]
fn generated_apex_kernels_match_central_differences() {
    use factor_core::host::HostKernel;
    use factor_testing::host::check_host_kernel;
    fn check_kernel<F: HostKernel<Apex>>(factor: &F) -> HostCheck {
        check_host_kernel::<F, Apex>(factor, 1e-4, |m, p, d, out| m.retract(p, d, out))
            .unwrap_or_else(|e| panic!("{}: {e}", F::NAME))
    }
    let mut sampler = Sampler::new(8);
    for _ in 0..50 {
        let checks = [
            check_kernel(&sampler.point_reprojection()),
            check_kernel(&sampler.line_reprojection()),
            check_kernel(&sampler.plane()),
            check_kernel(&sampler.free_line()),
            check_kernel(&sampler.plucker_line_reprojection()),
            check_kernel(&sampler.snavely_reprojection()),
            check_kernel(&sampler.stereo_reprojection()),
            check_kernel(&sampler.between()),
        ];
        for c in checks {
            assert!(c.max_error() < 1e-7, "{c:?}");
        }
    }
}
