//! The performance workloads W1..W4 (fewer points) give the CPU backend's pixels on the GPU:
//! exactly for W1 and W2 (flat or point-sampled, ONE/ONE), within 1/255 for W3 and W4
//! (bilinear filtering; their SRCALPHA/INVSRCALPHA piles take the exact blending path).

use pointillist_bench::workloads::{Kind, Workload};
use pointillist_testkit::{Tolerance, check_desc};

#[test]
fn workloads_match_the_cpu_backend() {
    for (kind, points, tol) in [
        (Kind::W1, 100_000, Tolerance::Exact),
        (Kind::W2, 100_000, Tolerance::Exact),
        (Kind::W3, 300, Tolerance::Steps(1)),
        (Kind::W4, 5_000, Tolerance::Steps(1)),
    ] {
        let w = Workload::new(kind, points);
        check_desc(&format!("workload_{kind:?}"), w.device_desc(), tol, |d| {
            w.configure(d)?;
            d.draw_point_list(w.fvf, &w.vertices)
        });
    }
}
