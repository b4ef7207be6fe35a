//! Rigid placements ([`Pose`]) and Plücker transforms ([`Xform`]).

use super::{Force, Mat3, Motion, Vec3};

/// The skew-symmetric matrix `[x]×` with `[x]× y = x × y`.
#[inline]
pub fn skew(x: &Vec3) -> Mat3 {
    Mat3::new(0.0, -x.z, x.y, x.z, 0.0, -x.x, -x.y, x.x, 0.0)
}

/// Rotation matrix of URDF roll-pitch-yaw angles: `R = Rz(yaw) · Ry(pitch) · Rx(roll)`
/// (fixed axes x, y, z), entry by entry as Drake's `RollPitchYaw::ToRotationMatrix`.
pub fn rotation_from_rpy(roll: f64, pitch: f64, yaw: f64) -> Mat3 {
    let (s0, c0) = roll.sin_cos();
    let (s1, c1) = pitch.sin_cos();
    let (s2, c2) = yaw.sin_cos();
    let (c2_s1, s2_s1) = (c2 * s1, s2 * s1);
    Mat3::new(
        c2 * c1,
        c2_s1 * s0 - s2 * c0,
        c2_s1 * c0 + s2 * s0,
        s2 * c1,
        s2_s1 * s0 + c2 * c0,
        s2_s1 * c0 - c2 * s0,
        -s1,
        c1 * s0,
        c1 * c0,
    )
}

/// Rotation by `angle` (rad) about the unit vector `axis`, with its sine and cosine given
/// (Rodrigues: `R = c·1 + s·[a]× + (1 − c)·a aᵀ`).
#[inline]
pub fn rotation_about_axis(axis: &Vec3, sin: f64, cos: f64) -> Mat3 {
    let (x, y, z) = (axis.x, axis.y, axis.z);
    let t = 1.0 - cos;
    let (tx, ty, tz) = (t * x, t * y, t * z);
    let (sx, sy, sz) = (sin * x, sin * y, sin * z);
    Mat3::new(
        tx * x + cos,
        tx * y - sz,
        tx * z + sy,
        tx * y + sz,
        ty * y + cos,
        ty * z - sx,
        tx * z - sy,
        ty * z + sx,
        tz * z + cos,
    )
}

/// A rigid placement `a_T_b`: where frame b is, seen from frame a.
///
/// `rot` maps b-coordinates to a-coordinates (its columns are b's axes in a) and `pos` is b's
/// origin in a-coordinates (m). A point `p_b` is at `rot · p_b + pos` in a.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// 3×3 rotation, b-coordinates to a-coordinates.
    pub rot: Mat3,
    /// b's origin in a-coordinates (m).
    pub pos: Vec3,
}

impl Default for Pose {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Pose {
    /// The identity placement.
    pub const IDENTITY: Pose = Pose {
        rot: Mat3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
        pos: Vec3::new(0.0, 0.0, 0.0),
    };

    /// A placement from a rotation and a translation.
    pub fn new(rot: Mat3, pos: Vec3) -> Self {
        Self { rot, pos }
    }

    /// The placement of a URDF `<origin xyz rpy>`.
    pub fn from_xyz_rpy(xyz: [f64; 3], rpy: [f64; 3]) -> Self {
        Self {
            rot: rotation_from_rpy(rpy[0], rpy[1], rpy[2]),
            pos: Vec3::new(xyz[0], xyz[1], xyz[2]),
        }
    }

    /// `a_T_c = a_T_b · b_T_c`.
    #[inline]
    pub fn compose(&self, b_t_c: &Pose) -> Pose {
        Pose {
            rot: self.rot * b_t_c.rot,
            pos: self.pos + self.rot * b_t_c.pos,
        }
    }

    /// `b_T_a`.
    pub fn inverse(&self) -> Pose {
        let rt = self.rot.transpose();
        Pose {
            rot: rt,
            pos: -(rt * self.pos),
        }
    }

    /// A point given in b-coordinates, in a-coordinates.
    #[inline]
    pub fn transform_point(&self, p_b: &Vec3) -> Vec3 {
        self.rot * p_b + self.pos
    }

    /// The Plücker transform `b_X_a` that carries motion from a-coordinates to b-coordinates.
    #[inline]
    pub fn to_xform(&self) -> Xform {
        Xform {
            e: self.rot.transpose(),
            r: self.pos,
        }
    }

    /// Whether every entry is finite.
    pub fn is_finite(&self) -> bool {
        self.rot.iter().chain(self.pos.iter()).all(|x| x.is_finite())
    }
}

/// A Plücker transform `B_X_A` (RBDA §2.8), stored as `(E, r)`:
///
/// ```text
///   B_X_A = [  E      0 ]        E: rotates A-coordinates into B-coordinates
///           [ -E[r]×  E ]        r: B's origin in A-coordinates (m)
/// ```
///
/// In the algorithms, `xup[i]` is `i_X_λ(i)`: from the parent body's frame to body i's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Xform {
    /// 3×3 rotation, A-coordinates to B-coordinates.
    pub e: Mat3,
    /// B's origin in A-coordinates (m).
    pub r: Vec3,
}

impl Default for Xform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Xform {
    /// The identity transform.
    pub const IDENTITY: Xform = Xform {
        e: Mat3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
        r: Vec3::new(0.0, 0.0, 0.0),
    };

    /// `X m`: a motion in A-coordinates, in B-coordinates: `(E ω, E (v − r × ω))`.
    #[inline]
    pub fn apply_motion(&self, m: &Motion) -> Motion {
        Motion {
            ang: self.e * m.ang,
            lin: self.e * (m.lin - self.r.cross(&m.ang)),
        }
    }

    /// `X⁻¹ m`: a motion in B-coordinates, in A-coordinates: `(Eᵀ ω, Eᵀ v + r × Eᵀ ω)`.
    #[inline]
    pub fn inv_apply_motion(&self, m: &Motion) -> Motion {
        let ang = self.e.tr_mul(&m.ang);
        Motion {
            ang,
            lin: self.e.tr_mul(&m.lin) + self.r.cross(&ang),
        }
    }

    /// `X* f`: a force in A-coordinates, in B-coordinates: `(E (n − r × f), E f)`.
    #[inline]
    pub fn apply_force(&self, f: &Force) -> Force {
        Force {
            ang: self.e * (f.ang - self.r.cross(&f.lin)),
            lin: self.e * f.lin,
        }
    }

    /// `Xᵀ f`: a force in B-coordinates, in A-coordinates: `(Eᵀ n + r × Eᵀ f, Eᵀ f)`.
    /// This is how a child's force reaches its parent in the backward passes.
    #[inline]
    pub fn transpose_apply_force(&self, f: &Force) -> Force {
        let lin = self.e.tr_mul(&f.lin);
        Force {
            ang: self.e.tr_mul(&f.ang) + self.r.cross(&lin),
            lin,
        }
    }

    /// `C_X_A = self · B_X_A` where `self` is `C_X_B`.
    #[inline]
    pub fn compose(&self, b_x_a: &Xform) -> Xform {
        Xform {
            e: self.e * b_x_a.e,
            r: b_x_a.r + b_x_a.e.tr_mul(&self.r),
        }
    }

    /// `A_X_B`.
    pub fn inverse(&self) -> Xform {
        Xform {
            e: self.e.transpose(),
            r: -(self.e * self.r),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Xform {
        Pose::from_xyz_rpy([0.1, -0.2, 0.35], [0.3, -1.1, 2.0]).to_xform()
    }

    #[test]
    fn rpy_matches_the_product_of_elementary_rotations() {
        let (r, p, y): (f64, f64, f64) = (0.4, -0.9, 2.5);
        let rx = rotation_about_axis(&Vec3::x(), r.sin(), r.cos());
        let ry = rotation_about_axis(&Vec3::y(), p.sin(), p.cos());
        let rz = rotation_about_axis(&Vec3::z(), y.sin(), y.cos());
        let d = rotation_from_rpy(r, p, y) - rz * ry * rx;
        assert!(d.abs().max() < 1e-15);
    }

    #[test]
    fn force_and_motion_transforms_preserve_power() {
        let x = sample();
        let m = Motion::new(Vec3::new(0.3, -1.2, 0.7), Vec3::new(2.0, 0.1, -0.4));
        let f = Force::new(Vec3::new(1.5, 0.4, -2.2), Vec3::new(-0.3, 0.7, 0.9));
        // (X m) · (X* f) = m · f and (X m) · f_B = m · (Xᵀ f_B)
        assert!((x.apply_motion(&m).dot(&x.apply_force(&f)) - m.dot(&f)).abs() < 1e-14);
        assert!((x.apply_motion(&m).dot(&f) - m.dot(&x.transpose_apply_force(&f))).abs() < 1e-14);
        let back = x.inv_apply_motion(&x.apply_motion(&m));
        assert!((back - m).ang.norm() + (back - m).lin.norm() < 1e-15);
    }

    #[test]
    fn compose_and_inverse_agree_with_poses() {
        let a = Pose::from_xyz_rpy([0.1, -0.2, 0.35], [0.3, -1.1, 2.0]);
        let b = Pose::from_xyz_rpy([-0.4, 0.5, 0.05], [-2.0, 0.2, 0.7]);
        // (a·b).to_xform() = b.to_xform() ∘ a.to_xform()
        let lhs = a.compose(&b).to_xform();
        let rhs = b.to_xform().compose(&a.to_xform());
        assert!((lhs.e - rhs.e).abs().max() < 1e-15 && (lhs.r - rhs.r).abs().max() < 1e-15);
        let id = a.to_xform().compose(&a.to_xform().inverse());
        assert!((id.e - Mat3::identity()).abs().max() < 1e-15 && id.r.norm() < 1e-15);
        let p = Vec3::new(0.3, 0.2, -0.1);
        assert!((a.inverse().transform_point(&a.transform_point(&p)) - p).norm() < 1e-15);
    }
}
