//! One draw, resolved once: what the device hands every backend.
//!
//! [`DrawSetup::new`] resolves the states of a draw (SPEC 2 to 5) into the per-point stage
//! ([`PointSetup`]), the pixel pipeline ([`PixelSetup`]) and the class of its blend
//! ([`BlendClass`]). The device resolves each draw once and passes it to
//! [`Backend::draw_points`](crate::device::Backend::draw_points); backends and tests read these
//! instead of resolving the states again, so every user of a rule reads one definition.

use crate::fvf::Fvf;
use crate::pixel::{BlendClass, PixelSetup};
use crate::point::PointSetup;
use crate::state::DeviceState;

/// A draw's states, resolved.
#[derive(Clone, Debug)]
pub struct DrawSetup<'a> {
    /// The state the draw was resolved from: the textures and sampler states a backend binds.
    pub state: &'a DeviceState,
    /// The vertex format.
    pub fvf: Fvf,
    /// The per-point stage (SPEC 1 to 4).
    pub points: PointSetup,
    /// The pixel pipeline (SPEC 5).
    pub pixel: PixelSetup,
    /// The class of `pixel.blend` (SPEC 5.5).
    pub blend: BlendClass,
}

impl<'a> DrawSetup<'a> {
    /// Resolves a draw of vertices of format `fvf` with `state`.
    pub fn new(state: &'a DeviceState, fvf: Fvf) -> DrawSetup<'a> {
        let pixel = PixelSetup::new(state);
        DrawSetup {
            state,
            fvf,
            points: PointSetup::new(state, fvf),
            blend: pixel.blend_class(),
            pixel,
        }
    }
}
