//! Rigid-body spatial inertia.

use super::{Force, Mat3, Motion, Vec3, Xform, skew};

/// The spatial inertia of a rigid body (or of several bodies welded together) about a frame's
/// origin, in that frame's coordinates (RBDA eq. 2.63):
///
/// ```text
///   I = [ Ī     [h]× ]      Ī: rotational inertia about the origin (kg·m²)
///       [ [h]×ᵀ  m·1 ]      h = m·c: first mass moment, c the centre of mass (kg·m)
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Inertia {
    /// Mass m (kg).
    pub mass: f64,
    /// First mass moment `h = m·c` (kg·m).
    pub h: Vec3,
    /// 3×3 rotational inertia about the frame origin, `Ī = I_c − m [c]×[c]×` (kg·m²).
    pub rot: Mat3,
}

impl Default for Inertia {
    fn default() -> Self {
        Self::ZERO
    }
}

impl Inertia {
    /// No mass at all.
    pub const ZERO: Inertia = Inertia {
        mass: 0.0,
        h: Vec3::new(0.0, 0.0, 0.0),
        rot: Mat3::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
    };

    /// A body of mass `mass` with its centre of mass at `com` and rotational inertia `i_com`
    /// about the centre of mass (parallel-axis theorem: `Ī = I_c − m [c]×[c]×`).
    pub fn from_com(mass: f64, com: Vec3, i_com: Mat3) -> Self {
        let cx = skew(&com);
        Self {
            mass,
            h: com * mass,
            rot: i_com - cx * cx * mass,
        }
    }

    /// A point mass at `p`.
    pub fn point_mass(mass: f64, p: Vec3) -> Self {
        Self::from_com(mass, p, Mat3::zeros())
    }

    /// `I m`: the momentum of a body moving with `m`: `(Ī ω + h × v, m v − h × ω)`.
    #[inline]
    pub fn mul_motion(&self, m: &Motion) -> Force {
        Force {
            ang: self.rot * m.ang + self.h.cross(&m.lin),
            lin: m.lin * self.mass - self.h.cross(&m.ang),
        }
    }

    /// `I (0, a)`: the momentum of a body translating with `a` and not rotating, `(h × a, m a)`
    /// ([`Inertia::mul_motion`] with the angular part known to be zero).
    #[inline]
    pub fn mul_translation(&self, a: &Vec3) -> Force {
        Force {
            ang: self.h.cross(a),
            lin: a * self.mass,
        }
    }

    /// Centre of mass (m); undefined for a massless body.
    pub fn com(&self) -> Vec3 {
        self.h / self.mass
    }

    /// Rotational inertia about the centre of mass, `I_c = Ī + m [c]×[c]×`.
    pub fn rot_about_com(&self) -> Mat3 {
        let hx = skew(&self.h);
        self.rot + hx * hx / self.mass
    }

    /// `Xᵀ I X`: this inertia, given in B-coordinates, expressed in A-coordinates, where `x` is
    /// `B_X_A`. With `y = Eᵀ h` (RBDA eq. 2.66 expanded, and `[a]×[b]× = b aᵀ − (a·b) 1`):
    ///
    /// ```text
    ///   h_A = y + m r
    ///   Ī_A = Eᵀ Ī E − m [r]×[r]× − [r]×[y]× − [y]×[r]×
    ///       = Eᵀ Ī E + (m r·r + 2 r·y) 1 − m r rᵀ − r yᵀ − y rᵀ
    /// ```
    #[inline]
    pub fn transform_to_source(&self, x: &Xform) -> Inertia {
        let (e, r) = (&x.e, &x.r);
        let y = e.tr_mul(&self.h);
        let mr = r * self.mass;
        let diag = mr.dot(r) + 2.0 * r.dot(&y);
        // symmetric: the upper triangle of Eᵀ (Ī E) − (m r rᵀ + r yᵀ + y rᵀ), mirrored
        let ie = self.rot * e;
        let entry = |a: usize, b: usize| e.column(a).dot(&ie.column(b)) - (mr[a] * r[b] + r[a] * y[b] + y[a] * r[b]);
        let (xx, yy, zz) = (entry(0, 0) + diag, entry(1, 1) + diag, entry(2, 2) + diag);
        let (xy, xz, yz) = (entry(0, 1), entry(0, 2), entry(1, 2));
        let rot = Mat3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz);
        Inertia {
            mass: self.mass,
            h: y + mr,
            rot,
        }
    }

    /// Whether every entry is finite.
    pub fn is_finite(&self) -> bool {
        self.mass.is_finite() && self.h.iter().chain(self.rot.iter()).all(|x| x.is_finite())
    }
}

impl std::ops::Add for Inertia {
    type Output = Inertia;
    fn add(self, o: Inertia) -> Inertia {
        Inertia {
            mass: self.mass + o.mass,
            h: self.h + o.h,
            rot: self.rot + o.rot,
        }
    }
}

impl std::ops::AddAssign for Inertia {
    #[inline]
    fn add_assign(&mut self, o: Inertia) {
        self.mass += o.mass;
        self.h += o.h;
        self.rot += o.rot;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spatial::Pose;

    #[test]
    fn transform_matches_the_force_motion_definition() {
        // (Xᵀ I X) m = Xᵀ (I (X m)) for any motion m.
        let i_b = Inertia::from_com(
            1.7,
            Vec3::new(0.05, -0.02, 0.11),
            Mat3::new(0.02, 0.001, -0.002, 0.001, 0.03, 0.0005, -0.002, 0.0005, 0.025),
        );
        let x = Pose::from_xyz_rpy([0.3, -0.1, 0.2], [0.7, 0.4, -1.3]).to_xform();
        let m = Motion::new(Vec3::new(0.3, -1.2, 0.7), Vec3::new(2.0, 0.1, -0.4));
        let lhs = i_b.transform_to_source(&x).mul_motion(&m);
        let rhs = x.transpose_apply_force(&i_b.mul_motion(&x.apply_motion(&m)));
        assert!((lhs - rhs).ang.norm() + (lhs - rhs).lin.norm() < 1e-14);
        // a pure translation through either product
        let a = Vec3::new(0.4, -9.81, 1.3);
        let d = i_b.mul_translation(&a) - i_b.mul_motion(&Motion::new(Vec3::zeros(), a));
        assert!(d.ang.norm() + d.lin.norm() < 1e-15);
        // round trip through the centre of mass
        let back = Inertia::from_com(i_b.mass, i_b.com(), i_b.rot_about_com());
        assert!((back.rot - i_b.rot).abs().max() < 1e-16);
    }
}
