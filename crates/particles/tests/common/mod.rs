//! Helpers shared by the integration tests: decoding the vertex bytes a system writes.

#![allow(dead_code)]

use pointillist_particles::{ParticleSystem, VERTEX_STRIDE};

/// One decoded `XYZ | PSIZE | DIFFUSE` vertex.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct V {
    pub p: [f32; 3],
    pub size: f32,
    pub color: u32,
}

pub fn decode(bytes: &[u8]) -> Vec<V> {
    assert_eq!(bytes.len() % VERTEX_STRIDE, 0);
    bytes
        .chunks_exact(VERTEX_STRIDE)
        .map(|v| {
            let w = |k: usize| u32::from_le_bytes(v[4 * k..4 * k + 4].try_into().unwrap());
            V {
                p: [
                    f32::from_bits(w(0)),
                    f32::from_bits(w(1)),
                    f32::from_bits(w(2)),
                ],
                size: f32::from_bits(w(3)),
                color: w(4),
            }
        })
        .collect()
}

pub fn vertices(system: &ParticleSystem) -> Vec<V> {
    let mut bytes = Vec::new();
    system.write_vertices(&mut bytes);
    decode(&bytes)
}
