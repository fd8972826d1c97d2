//! D3D-convention matrices (SPEC 1): rows, row vectors, `v' = v * M`, left-handed, clip space
//! `0 <= z <= w`, with the D3DX helpers a D3D9 program builds its transforms with.

/// A 4x4 matrix in D3D layout: `m.0[row][column]`, applied to row vectors as `v * M`.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Mat4(pub [[f32; 4]; 4]);

impl Default for Mat4 {
    fn default() -> Self {
        Mat4::IDENTITY
    }
}

fn sub3(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot3(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross3(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn normalize3(a: [f32; 3]) -> [f32; 3] {
    let len = dot3(a, a).sqrt();
    if len > 0.0 {
        [a[0] / len, a[1] / len, a[2] / len]
    } else {
        a
    }
}

/// Why D3DXMatrixLookAtLH gives no view for an eye, a point looked at and an up vector.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum LookAtError {
    /// `at` equals `eye`: there is no view direction.
    AtIsEye,
    /// `up` is parallel to `at - eye` (to within a millionth of a radian): there is no side
    /// direction.
    UpAlongView,
    /// The matrix overflows (vectors too large or too small).
    NotFinite,
}

impl LookAtError {
    /// The input to blame: `"at"`, `"up"` or `"eye"`.
    pub fn key(self) -> &'static str {
        match self {
            LookAtError::AtIsEye => "at",
            LookAtError::UpAlongView => "up",
            LookAtError::NotFinite => "eye",
        }
    }
}

impl std::fmt::Display for LookAtError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            LookAtError::AtIsEye => "`at` equals `eye`",
            LookAtError::UpAlongView => "`up` is parallel to the view direction `at - eye`",
            LookAtError::NotFinite => {
                "the view matrix is not finite (the vectors are too large or too small)"
            }
        })
    }
}

impl std::error::Error for LookAtError {}

/// SPEC 3.1: a subnormal value read as zero of the same sign, as GPU vertex stages read
/// subnormal inputs; every other value (zero, normal, infinite, NaN) unchanged.
#[inline]
pub fn flush_subnormal(v: f32) -> f32 {
    if v.is_subnormal() {
        0.0f32.copysign(v)
    } else {
        v
    }
}

impl Mat4 {
    /// The identity, the default of every D3DTS_* transform.
    pub const IDENTITY: Mat4 = Mat4([
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ]);

    /// `self * rhs`: a vector transformed by the result goes through `self` first, then `rhs`.
    pub fn mul(&self, rhs: &Mat4) -> Mat4 {
        let mut out = [[0.0f32; 4]; 4];
        for (r, row) in out.iter_mut().enumerate() {
            *row = rhs.transform(self.0[r]);
        }
        Mat4(out)
    }

    /// The matrix with every subnormal entry read as zero of its sign ([`flush_subnormal`],
    /// SPEC 3.1).
    pub fn flush_subnormals(&self) -> Mat4 {
        Mat4(self.0.map(|row| row.map(flush_subnormal)))
    }

    /// `v * self` for a row vector `v`.
    #[inline]
    pub fn transform(&self, v: [f32; 4]) -> [f32; 4] {
        let m = &self.0;
        let mut out = [0.0f32; 4];
        for (c, o) in out.iter_mut().enumerate() {
            *o = v[0] * m[0][c] + v[1] * m[1][c] + v[2] * m[2][c] + v[3] * m[3][c];
        }
        out
    }

    /// The transpose.
    pub fn transpose(&self) -> Mat4 {
        let mut out = [[0.0f32; 4]; 4];
        for (r, row) in out.iter_mut().enumerate() {
            for (c, v) in row.iter_mut().enumerate() {
                *v = self.0[c][r];
            }
        }
        Mat4(out)
    }

    /// The inverse, computed in f64; `None` when the matrix is singular or not finite.
    pub fn inverse(&self) -> Option<Mat4> {
        let m: Vec<f64> = self.0.iter().flatten().map(|&v| f64::from(v)).collect();
        let mut inv = [0.0f64; 16];
        // Cofactor expansion (the classic MESA gluInvertMatrix layout, row-major here).
        inv[0] = m[5] * m[10] * m[15] - m[5] * m[11] * m[14] - m[9] * m[6] * m[15]
            + m[9] * m[7] * m[14]
            + m[13] * m[6] * m[11]
            - m[13] * m[7] * m[10];
        inv[4] = -m[4] * m[10] * m[15] + m[4] * m[11] * m[14] + m[8] * m[6] * m[15]
            - m[8] * m[7] * m[14]
            - m[12] * m[6] * m[11]
            + m[12] * m[7] * m[10];
        inv[8] = m[4] * m[9] * m[15] - m[4] * m[11] * m[13] - m[8] * m[5] * m[15]
            + m[8] * m[7] * m[13]
            + m[12] * m[5] * m[11]
            - m[12] * m[7] * m[9];
        inv[12] = -m[4] * m[9] * m[14] + m[4] * m[10] * m[13] + m[8] * m[5] * m[14]
            - m[8] * m[6] * m[13]
            - m[12] * m[5] * m[10]
            + m[12] * m[6] * m[9];
        inv[1] = -m[1] * m[10] * m[15] + m[1] * m[11] * m[14] + m[9] * m[2] * m[15]
            - m[9] * m[3] * m[14]
            - m[13] * m[2] * m[11]
            + m[13] * m[3] * m[10];
        inv[5] = m[0] * m[10] * m[15] - m[0] * m[11] * m[14] - m[8] * m[2] * m[15]
            + m[8] * m[3] * m[14]
            + m[12] * m[2] * m[11]
            - m[12] * m[3] * m[10];
        inv[9] = -m[0] * m[9] * m[15] + m[0] * m[11] * m[13] + m[8] * m[1] * m[15]
            - m[8] * m[3] * m[13]
            - m[12] * m[1] * m[11]
            + m[12] * m[3] * m[9];
        inv[13] = m[0] * m[9] * m[14] - m[0] * m[10] * m[13] - m[8] * m[1] * m[14]
            + m[8] * m[2] * m[13]
            + m[12] * m[1] * m[10]
            - m[12] * m[2] * m[9];
        inv[2] = m[1] * m[6] * m[15] - m[1] * m[7] * m[14] - m[5] * m[2] * m[15]
            + m[5] * m[3] * m[14]
            + m[13] * m[2] * m[7]
            - m[13] * m[3] * m[6];
        inv[6] = -m[0] * m[6] * m[15] + m[0] * m[7] * m[14] + m[4] * m[2] * m[15]
            - m[4] * m[3] * m[14]
            - m[12] * m[2] * m[7]
            + m[12] * m[3] * m[6];
        inv[10] = m[0] * m[5] * m[15] - m[0] * m[7] * m[13] - m[4] * m[1] * m[15]
            + m[4] * m[3] * m[13]
            + m[12] * m[1] * m[7]
            - m[12] * m[3] * m[5];
        inv[14] = -m[0] * m[5] * m[14] + m[0] * m[6] * m[13] + m[4] * m[1] * m[14]
            - m[4] * m[2] * m[13]
            - m[12] * m[1] * m[6]
            + m[12] * m[2] * m[5];
        inv[3] = -m[1] * m[6] * m[11] + m[1] * m[7] * m[10] + m[5] * m[2] * m[11]
            - m[5] * m[3] * m[10]
            - m[9] * m[2] * m[7]
            + m[9] * m[3] * m[6];
        inv[7] = m[0] * m[6] * m[11] - m[0] * m[7] * m[10] - m[4] * m[2] * m[11]
            + m[4] * m[3] * m[10]
            + m[8] * m[2] * m[7]
            - m[8] * m[3] * m[6];
        inv[11] = -m[0] * m[5] * m[11] + m[0] * m[7] * m[9] + m[4] * m[1] * m[11]
            - m[4] * m[3] * m[9]
            - m[8] * m[1] * m[7]
            + m[8] * m[3] * m[5];
        inv[15] = m[0] * m[5] * m[10] - m[0] * m[6] * m[9] - m[4] * m[1] * m[10]
            + m[4] * m[2] * m[9]
            + m[8] * m[1] * m[6]
            - m[8] * m[2] * m[5];
        let det = m[0] * inv[0] + m[1] * inv[4] + m[2] * inv[8] + m[3] * inv[12];
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let mut out = [[0.0f32; 4]; 4];
        for (i, v) in inv.iter().enumerate() {
            out[i / 4][i % 4] = (v / det) as f32;
        }
        out.iter()
            .flatten()
            .all(|v| v.is_finite())
            .then_some(Mat4(out))
    }

    /// [`Mat4::look_at_lh`], or why these vectors give no view (a NaN or infinite matrix).
    /// Scene files refuse such cameras with this reason.
    pub fn look_at_checked(eye: [f32; 3], at: [f32; 3], up: [f32; 3]) -> Result<Mat4, LookAtError> {
        let dir = sub3(at, eye);
        if dir == [0.0; 3] {
            return Err(LookAtError::AtIsEye);
        }
        // Parallel to within a millionth of a radian: the side vector is then rounding noise.
        let len2 = |v: [f32; 3]| v.iter().map(|&x| f64::from(x).powi(2)).sum::<f64>();
        let side = cross3(up, dir);
        if len2(side) <= 1e-12 * len2(up) * len2(dir) {
            return Err(LookAtError::UpAlongView);
        }
        let m = Mat4::look_at_lh(eye, at, up);
        if m.0.iter().flatten().all(|v| v.is_finite()) {
            Ok(m)
        } else {
            Err(LookAtError::NotFinite)
        }
    }

    /// D3DXMatrixLookAtLH: a left-handed view matrix from the eye towards `at`.
    pub fn look_at_lh(eye: [f32; 3], at: [f32; 3], up: [f32; 3]) -> Mat4 {
        let z = normalize3(sub3(at, eye));
        let x = normalize3(cross3(up, z));
        let y = cross3(z, x);
        Mat4([
            [x[0], y[0], z[0], 0.0],
            [x[1], y[1], z[1], 0.0],
            [x[2], y[2], z[2], 0.0],
            [-dot3(x, eye), -dot3(y, eye), -dot3(z, eye), 1.0],
        ])
    }

    /// D3DXMatrixPerspectiveFovLH: `fovy` in radians, `aspect` = width / height.
    pub fn perspective_fov_lh(fovy: f32, aspect: f32, zn: f32, zf: f32) -> Mat4 {
        let ys = 1.0 / (fovy / 2.0).tan();
        let xs = ys / aspect;
        let q = zf / (zf - zn);
        Mat4([
            [xs, 0.0, 0.0, 0.0],
            [0.0, ys, 0.0, 0.0],
            [0.0, 0.0, q, 1.0],
            [0.0, 0.0, -zn * q, 0.0],
        ])
    }

    /// D3DXMatrixOrthoLH: a `w` x `h` view volume centred on the axis.
    pub fn ortho_lh(w: f32, h: f32, zn: f32, zf: f32) -> Mat4 {
        Mat4([
            [2.0 / w, 0.0, 0.0, 0.0],
            [0.0, 2.0 / h, 0.0, 0.0],
            [0.0, 0.0, 1.0 / (zf - zn), 0.0],
            [0.0, 0.0, zn / (zn - zf), 1.0],
        ])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f32; 4], b: [f32; 4]) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-5)
    }

    #[test]
    fn spec_1_row_vectors_translate_by_the_last_row() {
        let mut m = Mat4::IDENTITY;
        m.0[3] = [1.0, 2.0, 3.0, 1.0];
        assert_eq!(m.transform([1.0, 1.0, 1.0, 1.0]), [2.0, 3.0, 4.0, 1.0]);
    }

    #[test]
    fn spec_1_mul_applies_left_first() {
        let mut t = Mat4::IDENTITY;
        t.0[3] = [1.0, 0.0, 0.0, 1.0];
        let s = Mat4([
            [2.0, 0.0, 0.0, 0.0],
            [0.0, 2.0, 0.0, 0.0],
            [0.0, 0.0, 2.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ]);
        // translate, then scale: (0+1)*2 = 2
        assert_eq!(t.mul(&s).transform([0.0, 0.0, 0.0, 1.0])[0], 2.0);
        assert_eq!(s.mul(&t).transform([0.0, 0.0, 0.0, 1.0])[0], 1.0);
    }

    #[test]
    fn spec_1_look_at_puts_the_target_on_plus_z() {
        let v = Mat4::look_at_lh([0.0, 0.0, -5.0], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        assert!(close(
            v.transform([0.0, 0.0, 0.0, 1.0]),
            [0.0, 0.0, 5.0, 1.0]
        ));
        assert!(close(
            v.transform([1.0, 0.0, 0.0, 1.0]),
            [1.0, 0.0, 5.0, 1.0]
        ));
    }

    #[test]
    fn spec_1_perspective_maps_near_to_0_and_far_to_w() {
        let p = Mat4::perspective_fov_lh(std::f32::consts::FRAC_PI_2, 1.0, 1.0, 100.0);
        let near = p.transform([0.0, 0.0, 1.0, 1.0]);
        let far = p.transform([0.0, 0.0, 100.0, 1.0]);
        assert!(near[2].abs() < 1e-5 && near[3] == 1.0);
        assert!((far[2] - far[3]).abs() < 1e-3 && far[3] == 100.0);
        // 90 degrees: a point at 45 degrees lands on the top edge, y/w = 1
        let edge = p.transform([0.0, 10.0, 10.0, 1.0]);
        assert!((edge[1] / edge[3] - 1.0).abs() < 1e-5);
    }

    #[test]
    fn spec_1_ortho_maps_the_volume_to_clip_space() {
        let o = Mat4::ortho_lh(4.0, 2.0, 1.0, 3.0);
        assert!(close(
            o.transform([2.0, 1.0, 1.0, 1.0]),
            [1.0, 1.0, 0.0, 1.0]
        ));
        assert!(close(
            o.transform([-2.0, -1.0, 3.0, 1.0]),
            [-1.0, -1.0, 1.0, 1.0]
        ));
    }

    #[test]
    fn inverse_round_trips_and_rejects_singular() {
        let v = Mat4::look_at_lh([1.0, 2.0, -5.0], [0.5, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let p = Mat4::perspective_fov_lh(0.8, 1.3, 0.5, 50.0);
        let m = v.mul(&p);
        let i = m.inverse().unwrap();
        let r = m.mul(&i);
        for (a, b) in r.0.iter().zip(Mat4::IDENTITY.0.iter()) {
            assert!(close(*a, *b), "{r:?}");
        }
        assert!(Mat4([[0.0; 4]; 4]).inverse().is_none());
    }
}
