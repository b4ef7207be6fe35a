//! Spatial motion and force vectors.

use std::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

use super::Vec3;

/// A spatial motion vector `(ω, v)`: angular velocity and the linear velocity of the point at
/// the frame's origin, both in the frame's coordinates (also used for accelerations and for
/// joint motion subspaces).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Motion {
    /// Angular part ω (rad/s, or rad/s² for an acceleration).
    pub ang: Vec3,
    /// Linear part v of the frame origin (m/s, or m/s²).
    pub lin: Vec3,
}

/// A spatial force vector `(n, f)`: the moment about the frame's origin and the force, both in
/// the frame's coordinates (also used for momenta).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Force {
    /// Moment n about the frame origin (N·m).
    pub ang: Vec3,
    /// Force f (N).
    pub lin: Vec3,
}

impl Motion {
    /// The zero motion.
    pub const ZERO: Motion = Motion {
        ang: Vec3::new(0.0, 0.0, 0.0),
        lin: Vec3::new(0.0, 0.0, 0.0),
    };

    /// A motion from its angular and linear parts.
    pub fn new(ang: Vec3, lin: Vec3) -> Self {
        Self { ang, lin }
    }

    /// Motion cross product `self ×ₘ m` (RBDA eq. 2.31): `(ω×ωₘ, ω×vₘ + v×ωₘ)`.
    #[inline]
    pub fn cross_motion(&self, m: &Motion) -> Motion {
        Motion {
            ang: self.ang.cross(&m.ang),
            lin: self.ang.cross(&m.lin) + self.lin.cross(&m.ang),
        }
    }

    /// Force cross product `self ×* f` (RBDA eq. 2.32): `(ω×n + v×f, ω×f)`.
    #[inline]
    pub fn cross_force(&self, f: &Force) -> Force {
        Force {
            ang: self.ang.cross(&f.ang) + self.lin.cross(&f.lin),
            lin: self.ang.cross(&f.lin),
        }
    }

    /// The scalar product `m · f` (power, or a joint's generalised force `sᵀ f`).
    #[inline]
    pub fn dot(&self, f: &Force) -> f64 {
        self.ang.dot(&f.ang) + self.lin.dot(&f.lin)
    }

    /// Whether every component is finite.
    pub fn is_finite(&self) -> bool {
        self.ang.iter().chain(self.lin.iter()).all(|x| x.is_finite())
    }
}

impl Force {
    /// The zero force.
    pub const ZERO: Force = Force {
        ang: Vec3::new(0.0, 0.0, 0.0),
        lin: Vec3::new(0.0, 0.0, 0.0),
    };

    /// A force from its moment and linear parts.
    pub fn new(ang: Vec3, lin: Vec3) -> Self {
        Self { ang, lin }
    }
}

macro_rules! vector_ops {
    ($t:ident) => {
        impl Add for $t {
            type Output = $t;
            #[inline]
            fn add(self, o: $t) -> $t {
                $t {
                    ang: self.ang + o.ang,
                    lin: self.lin + o.lin,
                }
            }
        }
        impl Sub for $t {
            type Output = $t;
            #[inline]
            fn sub(self, o: $t) -> $t {
                $t {
                    ang: self.ang - o.ang,
                    lin: self.lin - o.lin,
                }
            }
        }
        impl AddAssign for $t {
            #[inline]
            fn add_assign(&mut self, o: $t) {
                self.ang += o.ang;
                self.lin += o.lin;
            }
        }
        impl SubAssign for $t {
            #[inline]
            fn sub_assign(&mut self, o: $t) {
                self.ang -= o.ang;
                self.lin -= o.lin;
            }
        }
        impl Neg for $t {
            type Output = $t;
            #[inline]
            fn neg(self) -> $t {
                $t {
                    ang: -self.ang,
                    lin: -self.lin,
                }
            }
        }
        impl Mul<f64> for $t {
            type Output = $t;
            #[inline]
            fn mul(self, s: f64) -> $t {
                $t {
                    ang: self.ang * s,
                    lin: self.lin * s,
                }
            }
        }
    };
}

vector_ops!(Motion);
vector_ops!(Force);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cross_products_are_dual() {
        // (v ×ₘ m) · f = -m · (v ×* f) for all v, m, f (RBDA eq. 2.33).
        let v = Motion::new(Vec3::new(0.3, -1.2, 0.7), Vec3::new(2.0, 0.1, -0.4));
        let m = Motion::new(Vec3::new(-0.5, 0.9, 1.1), Vec3::new(0.2, -0.8, 0.6));
        let f = Force::new(Vec3::new(1.5, 0.4, -2.2), Vec3::new(-0.3, 0.7, 0.9));
        let lhs = v.cross_motion(&m).dot(&f);
        let rhs = -m.dot(&v.cross_force(&f));
        assert!((lhs - rhs).abs() < 1e-14, "{lhs} vs {rhs}");
        // v ×ₘ v = 0
        let vv = v.cross_motion(&v);
        assert!(vv.ang.norm() + vv.lin.norm() < 1e-15);
    }
}
