//! The path on its grid: at each s_i the joint values and their derivatives along the path,
//! and the coefficients of the torque the motion needs (docs/retime.md, "Constraints").
//!
//! Along q(s) with path speed ṡ and acceleration s̈, q̇ = q' ṡ and q̈ = q' s̈ + q'' ṡ², so the
//! inverse dynamics M q̈ + C(q, q̇) q̇ + g is, in x = ṡ² and u = s̈,
//!
//! ```text
//!   τ(s) = a(s) u + b(s) x + c(s),    a = M q',   b = M q'' + C(q, q') q',   c = g(q)
//! ```
//!
//! (C is linear in its velocity argument). One kinematics pass per grid point gives M, g and
//! C(q, q') q' + g ([`compute_all_terms`]): the model's payload and the motors' reflected rotor
//! inertia are in M as in the closed loop.

use super::spline::PathSpline;
use crate::algo::{Data, compute_all_terms};
use crate::model::Model;

/// The path sampled on a uniform grid s_i = L·i/N, i = 0 … N, and the torque coefficients.
/// Per-point arrays are point-major, `dof` entries per point.
#[derive(Clone, Debug)]
pub(crate) struct PathGrid {
    /// Joints.
    pub dof: usize,
    /// s_i (rad or m of path length), N + 1.
    pub s: Vec<f64>,
    /// q(s_i) (rad or m).
    pub q: Vec<f64>,
    /// q'(s_i) = dq/ds (joint units per unit of s).
    pub dq: Vec<f64>,
    /// q''(s_i) = d²q/ds².
    pub ddq: Vec<f64>,
    /// a(s_i) = M q' (N·m or N per unit s̈).
    pub a: Vec<f64>,
    /// b(s_i) = M q'' + C(q, q') q' (N·m or N per unit ṡ²).
    pub b: Vec<f64>,
    /// c(s_i) = g(q) (N·m or N).
    pub c: Vec<f64>,
}

impl PathGrid {
    /// `spline` on `intervals` (≥ 1) equal intervals, with the torque coefficients of `model`.
    pub fn new(model: &Model, spline: &PathSpline, intervals: usize) -> PathGrid {
        let dof = spline.dof();
        let points = intervals + 1;
        let length = spline.length();
        let mut grid = PathGrid {
            dof,
            s: (0..points).map(|i| length * i as f64 / intervals as f64).collect(),
            q: vec![0.0; points * dof],
            dq: vec![0.0; points * dof],
            ddq: vec![0.0; points * dof],
            a: vec![0.0; points * dof],
            b: vec![0.0; points * dof],
            c: vec![0.0; points * dof],
        };
        grid.s[intervals] = length;
        let mut data = Data::new(model);
        for i in 0..points {
            let at = i * dof..(i + 1) * dof;
            spline.eval(
                grid.s[i],
                &mut grid.q[at.clone()],
                &mut grid.dq[at.clone()],
                &mut grid.ddq[at.clone()],
            );
            compute_all_terms(model, &mut data, &grid.q[at.clone()], &grid.dq[at.clone()]);
            // a = M q',  b = M q'' + (C q' + g) − g,  c = g
            for j in 0..dof {
                let (mut mq1, mut mq2) = (0.0, 0.0);
                for k in 0..dof {
                    mq1 += data.m[(j, k)] * grid.dq[i * dof + k];
                    mq2 += data.m[(j, k)] * grid.ddq[i * dof + k];
                }
                grid.a[i * dof + j] = mq1;
                grid.b[i * dof + j] = mq2 + data.bias[j] - data.g[j];
                grid.c[i * dof + j] = data.g[j];
            }
        }
        grid
    }

    /// Number of grid points N + 1.
    pub fn points(&self) -> usize {
        self.s.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algo::rnea;

    /// τ = a u + b x + c is the inverse dynamics of q̇ = q'ṡ, q̈ = q's̈ + q''ṡ² for any (ṡ, s̈).
    #[test]
    fn the_coefficients_give_the_inverse_dynamics() {
        let model = crate::faze4::model();
        let points: Vec<Vec<f64>> = (0..6)
            .map(|k| (0..6).map(|j| 0.3 * ((k * 7 + j * 3) as f64).sin()).collect())
            .collect();
        let spline = PathSpline::through(&points).unwrap();
        let grid = PathGrid::new(&model, &spline, 20);
        let mut data = Data::new(&model);
        let (sd, sdd) = (1.7, -2.3);
        for i in [0, 7, 20] {
            let at = i * 6..(i + 1) * 6;
            let qd: Vec<f64> = grid.dq[at.clone()].iter().map(|d| d * sd).collect();
            let qdd: Vec<f64> = (grid.dq[at.clone()].iter().zip(&grid.ddq[at.clone()]))
                .map(|(d1, d2)| d1 * sdd + d2 * sd * sd)
                .collect();
            let tau = rnea(&model, &mut data, &grid.q[at.clone()], &qd, &qdd);
            for j in 0..6 {
                let ours = grid.a[i * 6 + j] * sdd + grid.b[i * 6 + j] * sd * sd + grid.c[i * 6 + j];
                assert!(
                    (ours - tau[j]).abs() < 1e-12 * (1.0 + tau[j].abs()),
                    "J{} at {i}",
                    j + 1
                );
            }
        }
    }
}
