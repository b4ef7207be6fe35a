//! MJCF's numbers: attribute lists, a frame's orientation in its five forms (MuJoCo's
//! conventions, `user_util.cc`), and the mass and inertia of a primitive geom
//! (`mjCGeom::ComputeInertia`).

use std::f64::consts::PI;

use crate::spatial::{Mat3, Pose, Vec3};

/// How the model writes angles and Euler sequences (`<compiler angle eulerseq>`).
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Angles {
    /// Whether angles are in degrees (MuJoCo's default) rather than radians.
    pub degrees: bool,
    /// The Euler sequence: three of `xyzXYZ`, lower case about the rotating axes (intrinsic),
    /// upper case about the fixed ones (extrinsic).
    pub eulerseq: [u8; 3],
}

impl Default for Angles {
    fn default() -> Self {
        Angles {
            degrees: true,
            eulerseq: *b"xyz",
        }
    }
}

impl Angles {
    /// An angle as written, in radians.
    pub fn radians(&self, a: f64) -> f64 {
        match self.degrees {
            true => a * PI / 180.0,
            false => a,
        }
    }
}

/// The numbers of attribute value `text`, separated by white space; `Err` names the word that
/// is not one.
pub(super) fn numbers(text: &str) -> std::result::Result<Vec<f64>, String> {
    (text.split_ascii_whitespace())
        .map(|w| w.parse::<f64>().map_err(|_| format!("'{w}' is not a number")))
        .collect()
}

/// A quaternion (w, x, y, z), normalised, as a rotation matrix; a zero one is the identity.
pub(super) fn quat_matrix(q: [f64; 4]) -> Mat3 {
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    if n == 0.0 || !n.is_finite() {
        return Mat3::identity();
    }
    let [w, x, y, z] = q.map(|c| c / n);
    Mat3::new(
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y - w * z),
        2.0 * (x * z + w * y),
        2.0 * (x * y + w * z),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z - w * x),
        2.0 * (x * z - w * y),
        2.0 * (y * z + w * x),
        1.0 - 2.0 * (x * x + y * y),
    )
}

/// The product of quaternions `a ⊗ b`.
fn quat_mul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// The quaternion of a rotation by `angle` (rad) about `axis` (normalised here).
pub(super) fn axis_angle_quat(axis: [f64; 3], angle: f64) -> [f64; 4] {
    let v = Vec3::from(axis);
    let n = v.norm();
    let u = if n > 0.0 { v / n } else { v };
    let (s, c) = (angle / 2.0).sin_cos();
    [c, u.x * s, u.y * s, u.z * s]
}

/// `euler` (radians) in the sequence `seq`: each rotation multiplies on the right when its
/// letter is lower case (about the axes rotated so far), on the left when upper case.
pub(super) fn euler_quat(euler: [f64; 3], seq: [u8; 3]) -> [f64; 4] {
    let mut q = [1.0, 0.0, 0.0, 0.0];
    for (a, axis) in euler.into_iter().zip(seq) {
        let unit = match axis.to_ascii_lowercase() {
            b'x' => [1.0, 0.0, 0.0],
            b'y' => [0.0, 1.0, 0.0],
            _ => [0.0, 0.0, 1.0],
        };
        let r = axis_angle_quat(unit, a);
        q = match axis.is_ascii_lowercase() {
            true => quat_mul(q, r),
            false => quat_mul(r, q),
        };
    }
    q
}

/// The frame whose x and y axes are `x` and `y` (y made orthogonal to x; z = x × y).
pub(super) fn xyaxes_matrix(x: [f64; 3], y: [f64; 3]) -> Mat3 {
    let x = Vec3::from(x).normalize();
    let y = Vec3::from(y);
    let y = (y - x * x.dot(&y)).normalize();
    let z = x.cross(&y).normalize();
    Mat3::from_columns(&[x, y, z])
}

/// The smallest rotation that takes (0, 0, 1) to `z` (a half turn about x when `z` points down).
pub(super) fn zaxis_quat(z: [f64; 3]) -> [f64; 4] {
    let v = Vec3::from(z);
    let v = v / v.norm();
    let axis = Vec3::z().cross(&v);
    let s = axis.norm();
    let unit = if s < 1e-10 { Vec3::x() } else { axis / s };
    let angle = s.atan2(v.z);
    axis_angle_quat([unit.x, unit.y, unit.z], angle)
}

/// A primitive geom's volume (m³) and its rotational inertia per unit density about its centre
/// in its own frame (principal moments x, y, z), from its MJCF `size` (half sizes, radius and
/// half length). `None` for a shape without volume.
pub(super) fn unit_inertia(kind: &str, size: &[f64]) -> Option<(f64, [f64; 3])> {
    let s = |i: usize| size.get(i).copied().unwrap_or(0.0);
    Some(match kind {
        "sphere" => {
            let r = s(0);
            let v = 4.0 / 3.0 * PI * r * r * r;
            (v, [2.0 / 5.0 * v * r * r; 3])
        }
        "capsule" => {
            let (r, h) = (s(0), 2.0 * s(1));
            let (vc, vs) = (PI * r * r * h, 4.0 / 3.0 * PI * r * r * r);
            let across = vc * (3.0 * r * r + h * h) / 12.0 + vs * (2.0 * r * r / 5.0 + h * h / 4.0 + 3.0 * h * r / 8.0);
            (vc + vs, [across, across, vc * r * r / 2.0 + vs * 2.0 * r * r / 5.0])
        }
        "cylinder" => {
            let (r, h) = (s(0), 2.0 * s(1));
            let v = PI * r * r * h;
            let across = v * (3.0 * r * r + h * h) / 12.0;
            (v, [across, across, v * r * r / 2.0])
        }
        "ellipsoid" => {
            let (a, b, c) = (s(0), s(1), s(2));
            let v = 4.0 / 3.0 * PI * a * b * c;
            (
                v,
                [
                    v * (b * b + c * c) / 5.0,
                    v * (a * a + c * c) / 5.0,
                    v * (a * a + b * b) / 5.0,
                ],
            )
        }
        "box" => {
            let (a, b, c) = (s(0), s(1), s(2));
            let v = 8.0 * a * b * c;
            (
                v,
                [
                    v * (b * b + c * c) / 3.0,
                    v * (a * a + c * c) / 3.0,
                    v * (a * a + b * b) / 3.0,
                ],
            )
        }
        _ => return None,
    })
}

/// The placement of a capsule, cylinder, box or ellipsoid given by `fromto` (two points): its
/// centre between them, its z axis from the first to the second; and its half length.
pub(super) fn fromto_pose(p: [f64; 6]) -> (Pose, f64) {
    let (a, b) = (Vec3::new(p[0], p[1], p[2]), Vec3::new(p[3], p[4], p[5]));
    let d = b - a;
    let rot = quat_matrix(zaxis_quat([d.x, d.y, d.z]));
    (Pose::new(rot, (a + b) / 2.0), d.norm() / 2.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: &Mat3, b: &Mat3) -> bool {
        (a - b).abs().max() < 1e-15
    }

    #[test]
    fn the_five_orientations_agree_on_one_rotation() {
        // a quarter turn about z, written five ways
        let expected = Mat3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0);
        let half = std::f64::consts::FRAC_PI_2;
        assert!(close(&quat_matrix([1.0, 0.0, 0.0, 1.0]), &expected));
        assert!(close(&quat_matrix(axis_angle_quat([0.0, 0.0, 2.0], half)), &expected));
        assert!(close(&quat_matrix(euler_quat([0.0, 0.0, half], *b"xyz")), &expected));
        assert!(close(&xyaxes_matrix([0.0, 1.0, 0.0], [-1.0, 0.5, 0.0]), &expected));
        // zaxis: the smallest rotation; pointing down, a half turn about x
        let down = quat_matrix(zaxis_quat([0.0, 0.0, -3.0]));
        assert!(close(&down, &Mat3::new(1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, -1.0)));
    }

    #[test]
    fn intrinsic_and_extrinsic_sequences_differ_by_their_order() {
        let (a, b) = (0.3, -0.7);
        let intrinsic = quat_matrix(euler_quat([a, b, 0.0], *b"xyz"));
        let extrinsic = quat_matrix(euler_quat([a, b, 0.0], *b"XYZ"));
        let rx = quat_matrix(axis_angle_quat([1.0, 0.0, 0.0], a));
        let ry = quat_matrix(axis_angle_quat([0.0, 1.0, 0.0], b));
        assert!(close(&intrinsic, &(rx * ry)));
        assert!(close(&extrinsic, &(ry * rx)));
    }
}
