//! `--self-collisions`: contact forces between the checked pairs of the arm's own collision
//! geometry, solved inside the discrete step (docs/contact.md).

use crate::algo::{
    ContactPoint, ContactSolver, Data, State, forward_kinematics_from_transforms, integrate_discrete_with_contacts,
};
use crate::error::{Error, Result, shortest};
use std::sync::Arc;

use super::check::non_negative;

use crate::geometry::{CollisionSet, ContactData, ContactGeometry, REFRESH_EVERY, REFRESH_MOTION};
use crate::model::{JointId, JointKind, Model};
use crate::spatial::Vec3;

/// Drake's default point-contact stiffness of one geometry (N/m).
pub const POINT_STIFFNESS: f64 = 1e6;
/// Drake's default Hunt–Crossley dissipation (s/m).
pub const HUNT_CROSSLEY_DISSIPATION: f64 = 50.0;

/// How the arm's collision geometry touches itself. The defaults are Drake's: every geometry
/// of stiffness 1e6 N/m (two in contact combine in series, 5e5 N/m), dissipation 50 s/m,
/// friction 1.0. Which pairs touch and how meshes are read are the run's collision settings
/// ([`super::Collisions`]: with `Hull` the convex hulls touch, as in Drake; with `Mesh` two
/// intersecting meshes stop the run, see [`crate::error::Error::MeshContact`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SelfContact {
    /// Coulomb friction μ (≥ 0), `--friction`.
    pub friction: f64,
    /// Stiffness of each geometry (N/m, > 0).
    pub stiffness: f64,
    /// Hunt–Crossley dissipation of each geometry (s/m, ≥ 0).
    pub dissipation: f64,
    /// A penetrating pair is queried again after at most this many steps (≥ 1; 1: every
    /// step); between queries its contact is followed rigidly (docs/contact.md).
    pub refresh_every: u32,
    /// ... or sooner, once its shapes have moved this far relative to each other (m, ≥ 0).
    pub refresh_motion: f64,
}

impl Default for SelfContact {
    fn default() -> Self {
        SelfContact {
            friction: 1.0,
            stiffness: POINT_STIFFNESS,
            dissipation: HUNT_CROSSLEY_DISSIPATION,
            refresh_every: REFRESH_EVERY,
            refresh_motion: REFRESH_MOTION,
        }
    }
}

/// Largest Coulomb friction `friction` takes. The contact step's products of μ overflow
/// between 1e150 and 1e200 (μ = 1e200 gave the frictionless result); every μ from about 1e10
/// gave the same sticking run as 1e100 (the circle shape with `self_collisions`).
pub const MAX_FRICTION: f64 = 1e100;

impl SelfContact {
    /// Checks the settings, naming `friction` (≥ 0, at most [`MAX_FRICTION`]) and the
    /// contact's stiffness (> 0) and dissipation (≥ 0).
    pub fn check(&self) -> Result<()> {
        non_negative("friction", self.friction)?;
        if self.friction > MAX_FRICTION {
            return Err(Error::option(
                "friction",
                format!(
                    "{}: at most {MAX_FRICTION:e}: beyond it the contact solver's arithmetic overflows (any μ above about 1e10 already sticks)",
                    shortest(self.friction)
                ),
            ));
        }
        let contact = |what: &str, x: f64, rule: &str| {
            Error::option(
                "self_collisions",
                format!("the contact's {what} {} must be {rule}", shortest(x)),
            )
        };
        if !(self.stiffness.is_finite() && self.stiffness > 0.0) {
            return Err(contact("stiffness", self.stiffness, "finite and > 0"));
        }
        if !(self.dissipation.is_finite() && self.dissipation >= 0.0) {
            return Err(contact("dissipation", self.dissipation, "finite and ≥ 0"));
        }
        Ok(())
    }
}

/// The discrete step with self-contact: the contact geometry, its workspace and the solver's.
pub struct ContactStep {
    settings: SelfContact,
    geometry: ContactGeometry,
    data: ContactData,
    solver: ContactSolver,
    /// Steps that had at least one contact.
    pub steps_in_contact: u64,
    /// Deepest penetration seen (m, ≥ 0).
    pub max_depth: f64,
    /// Newton iterations over the run.
    pub newton_iterations: u64,
    /// q at the previous step, and |Δq| since (per joint).
    last_q: Vec<f64>,
    joint_motion: Vec<f64>,
}

impl ContactStep {
    /// Contact between the objects of `set` (loaded for `model`) as `settings` say.
    pub fn new(model: &Model, set: Arc<CollisionSet>, settings: SelfContact) -> ContactStep {
        let geometry = ContactGeometry::new(model, set);
        let mut data = geometry.data();
        data.refresh_every = settings.refresh_every.max(1);
        data.refresh_motion = settings.refresh_motion;
        ContactStep {
            settings,
            data,
            geometry,
            solver: ContactSolver::new(model),
            steps_in_contact: 0,
            max_depth: 0.0,
            newton_iterations: 0,
            last_q: Vec::new(),
            joint_motion: vec![0.0; model.dof()],
        }
    }

    /// The loaded contact geometry.
    pub fn geometry(&self) -> &ContactGeometry {
        &self.geometry
    }

    /// Pair queries of the geometry so far.
    pub fn geometry_queries(&self) -> u64 {
        self.data.queries
    }

    /// The contacts of the last step.
    pub fn contacts(&self) -> &[crate::geometry::Contact] {
        &self.data.contacts
    }

    /// One step of `state` at time `t` (s): the world poses, the contacts at q, their
    /// Jacobians, and [`integrate_discrete_with_contacts`]. `data.xup`, `data.m` and `data.bias`
    /// must be at (q, v) ([`crate::algo::compute_all_terms`]).
    pub fn step(&mut self, model: &Model, data: &mut Data, state: &mut State, t: f64) -> Result<()> {
        forward_kinematics_from_transforms(model, data);
        if self.last_q.is_empty() {
            self.last_q.extend_from_slice(&state.q);
        }
        for ((m, last), now) in self.joint_motion.iter_mut().zip(&mut self.last_q).zip(state.q.iter()) {
            *m = (now - *last).abs();
            *last = *now;
        }
        self.geometry
            .find(&data.frame_pose, &self.joint_motion, t, &mut self.data)?;
        self.solver.clear();
        let s = &self.settings;
        // two equal geometries: stiffness in series k/2, dissipation (k_b d_a + k_a d_b)/(k_a + k_b) = d
        let point = |phi| ContactPoint {
            phi,
            stiffness: s.stiffness * s.stiffness / (s.stiffness + s.stiffness),
            dissipation: s.dissipation,
            friction: s.friction,
        };
        for c in &self.data.contacts {
            self.max_depth = self.max_depth.max(-c.phi);
            let rows = self.solver.push(point(c.phi));
            contact_jacobian(model, data, c, rows);
        }
        self.steps_in_contact += u64::from(!self.data.contacts.is_empty());
        let stepped = integrate_discrete_with_contacts(model, data, state, &mut self.solver);
        self.newton_iterations += self.solver.iterations as u64;
        stepped
    }
}

/// The 3×n Jacobian (row-major into `rows`) of the velocity of the second body relative to the
/// first at the contact point p, in the contact frame (t₁, t₂, n̂): for each joint j on the
/// path of body B (sign +1) or body A (−1) to the root, world axis a and origin o, the column
/// `±(a × (p − o))` (revolute) or `±a` (prismatic), then rotated into the frame. Joints both
/// paths share cancel; a mimic follower's column goes to its leader's, times m. Requires the
/// world poses at q.
fn contact_jacobian(model: &Model, data: &Data, c: &crate::geometry::Contact, rows: &mut [f64]) {
    let n = model.dof();
    let normal = c.normal;
    // any unit tangent, then t₂ = n̂ × t₁
    let helper = if normal.x.abs() < 0.9 { Vec3::x() } else { Vec3::y() };
    let t1 = normal.cross(&helper).normalize();
    let t2 = normal.cross(&t1);
    for (body, sign) in [(c.bodies[1], 1.0), (c.bodies[0], -1.0)] {
        let mut joint = body.map(|JointId(j)| j);
        while let Some(j) = joint {
            let pose = &data.body_pose[j];
            let moved = &model.bodies[j];
            let axis = pose.rot * moved.axis;
            let column = match moved.kind {
                JointKind::Revolute | JointKind::Continuous => axis.cross(&(c.point - pose.pos)),
                JointKind::Prismatic => axis,
            } * sign;
            // a follower's body moves with m times its leader's coordinate (J G)
            let (i, column) = match moved.follower {
                false => (moved.coordinate, column),
                true => (moved.coordinate, column * moved.multiplier),
            };
            rows[i] += t1.dot(&column);
            rows[n + i] += t2.dot(&column);
            rows[2 * n + i] += normal.dot(&column);
            joint = model.parent[j];
        }
    }
}
