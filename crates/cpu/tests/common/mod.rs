//! Helpers shared by the CPU backend's integration tests: the tests' random stream ([`Rng`],
//! pointillist-fixtures', which the unit tests use too) and a comparison of two targets.

use pointillist_core::device::RenderTarget;

pub(crate) use pointillist_fixtures::Rng;

/// Asserts that `a` and `b` hold the same colours and the same depth bits; `what` names the
/// comparison in the failure message.
pub fn assert_same_target(a: &RenderTarget, b: &RenderTarget, what: &str) {
    let differing = a.color.iter().zip(&b.color).filter(|(x, y)| x != y).count();
    assert_eq!(differing, 0, "{what}: {differing} pixels differ");
    assert!(
        a.depth
            .iter()
            .zip(&b.depth)
            .all(|(x, y)| x.to_bits() == y.to_bits()),
        "{what}: depths differ"
    );
}
