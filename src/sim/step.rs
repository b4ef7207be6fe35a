//! One step of the closed loop, stage by stage, as MuJoCo's `mj_step` (docs/model.md): an
//! immutable [`Scenario`] and one mutable [`Step`] workspace, each stage a free function of the
//! two. [`super::run`] is these stages in a loop, with the metrics and the recorders.
//!
//! A step at time t_k = k·Δt, in order:
//!
//! | stage | (inputs) ⇒ (outputs) |
//! |---|---|
//! | [`dynamics`] | (q, v) ⇒ (M, C v + g, g) in [`Step::data`] |
//! | [`command`] | t ⇒ (q_cmd, v_cmd); under `ff` full also a_cmd and τ_ff |
//! | [`controller`] | (q, v, q_cmd, v_cmd, g or τ_ff) ⇒ τ_raw |
//! | [`actuation`] | (τ_raw, q, v, q_cmd, motors, t) ⇒ (τ, the allowed range; a servo's goal) |
//! | [`sample`] | (q, v, q_cmd, v_cmd, τ, τ_raw, g) ⇒ the [`Sample`] a recorder gets |
//! | [`integrate`] | (M, C v + g, τ, q, v) ⇒ (q, v) at t + Δt |
//!
//! [`step`] runs the five that change the state. Stepping a scenario by hand:
//!
//! ```no_run
//! use faze4::sim::{self, Scenario, Step};
//! use faze4::traj::{Trajectory, Wave};
//! # fn main() -> faze4::Result<()> {
//! let model = faze4::faze4::model();
//! let wave = Trajectory::Wave(Wave { amplitude: vec![0.3; model.dof()], omega: 0.5, center: vec![0.0; model.dof()] });
//! let scenario = Scenario::builder(model, wave).duration(1.0).build()?;
//! let mut s = Step::new(&scenario);
//! for k in 0..scenario.steps {
//!     sim::step(&scenario, &mut s, k as f64 * scenario.dt)?;
//! }
//! println!("q at the end: {:?}", s.state.q);
//! # Ok(())
//! # }
//! ```
//!
//! Nothing is allocated after [`Step::new`].

use crate::algo::{Data, State, compute_all_terms, frame_position, integrate_discrete, rnea};
use crate::control::FeedForward;
use crate::error::Result;
use crate::spatial::Vec3;

use super::drives::{self, Servos};
use super::{ContactStep, Sample, Scenario};
use crate::control::ServoState;

/// The closed loop's mutable state and workspaces for one [`Scenario`] (n = its model's dof).
pub struct Step {
    /// The rigid-body workspace: after [`dynamics`], M (n×n), C v + g (n) and g (n) at (q, v),
    /// in joint space; the frames' poses in the world.
    pub data: Data,
    /// q, v (n each, rad or m, rad/s or m/s), the joint torques τ held over the step (n, N·m or
    /// N), Δt (s).
    pub state: State,
    /// The command at the step's time: positions (n, rad or m).
    pub q_cmd: Vec<f64>,
    /// The command's velocities (n, rad/s or m/s).
    pub v_cmd: Vec<f64>,
    /// The controller's torque before actuation, τ_raw (n, N·m or N).
    pub tau_raw: Vec<f64>,
    /// The joint torque range [lo, hi] each joint's actuation allowed this step (n, N·m or N):
    /// the effort limits, within each motor's envelope at the joint's speed under `motors`.
    pub bounds: Vec<(f64, f64)>,
    /// Under `ff` full: the command's acceleration a_cmd (n), and the workspace of its inverse
    /// dynamics, τ_ff in its `tau` (a second `Data`: the first holds the measured state's terms).
    full_ff: Option<(Vec<f64>, Data)>,
    /// `self_collisions`: the step with contact.
    pub(super) contact: Option<ContactStep>,
    /// Under `drive` servo: each joint's servo state and the goals sent.
    pub(super) servos: Option<Servos>,
    /// The shape's target and its rate at the sample (world, m and m/s; buffers).
    target: [f64; 3],
    target_rate: [f64; 3],
}

impl Step {
    /// In the command's start state ([`crate::traj::Trajectory::start_state`]), at rest in every other respect; under `drive`
    /// stepper, each stepper's joint at its static lag behind the first microstep.
    pub fn new(sc: &Scenario) -> Self {
        let model = &sc.model;
        let n = model.dof();
        let mut state = State::new(model, sc.dt);
        sc.trajectory.start_state(&mut state.q, &mut state.v);
        let mut data = Data::new(model);
        drives::settle(sc, &mut data, &mut state);
        let contact = (sc.self_contact.zip(sc.collision_set.clone()))
            .map(|(settings, set)| ContactStep::new(model, set, settings));
        Step {
            data,
            state,
            q_cmd: vec![0.0; n],
            v_cmd: vec![0.0; n],
            tau_raw: vec![0.0; n],
            bounds: vec![(f64::NEG_INFINITY, f64::INFINITY); n],
            full_ff: (sc.controller.feedforward == FeedForward::Full).then(|| (vec![0.0; n], Data::new(model))),
            contact,
            servos: Servos::new(sc),
            target: [0.0; 3],
            target_rate: [0.0; 3],
        }
    }
}

impl Step {
    /// Joint `i`'s smart servo's state under `drive` servo (its goal, its protection's trip),
    /// `None` for a joint without one.
    pub fn servo(&self, sc: &Scenario, i: usize) -> Option<&ServoState> {
        sc.drives.get(i)?.servo()?;
        self.servos.as_ref().map(|s| &s.states[i])
    }
}

/// (q, v) ⇒ M, C v + g and g in `s.data`, from one kinematics pass.
#[inline]
pub fn dynamics(sc: &Scenario, s: &mut Step) {
    compute_all_terms(&sc.model, &mut s.data, &s.state.q, &s.state.v);
}

/// t (s) ⇒ q_cmd, v_cmd; under `ff` full also a_cmd and
/// τ_ff = M(q_cmd) a_cmd + C(q_cmd, v_cmd) v_cmd + g(q_cmd) (RNEA).
#[inline]
pub fn command(sc: &Scenario, s: &mut Step, t: f64) {
    match &mut s.full_ff {
        None => sc.trajectory.eval(t, &mut s.q_cmd, &mut s.v_cmd),
        Some((a_cmd, data)) => {
            sc.trajectory
                .eval_with_acceleration(t, &mut s.q_cmd, &mut s.v_cmd, a_cmd);
            rnea(&sc.model, data, &s.q_cmd, &s.v_cmd, a_cmd);
        }
    }
}

/// (q, v, q_cmd, v_cmd, g or τ_ff) ⇒ τ_raw: the PD torque with gravity or the command's
/// inverse dynamics fed forward.
#[inline]
pub fn controller(sc: &Scenario, s: &mut Step) {
    let State { q, v, .. } = &s.state;
    let ff = match &s.full_ff {
        Some((_, data)) => data.tau.as_slice(),
        None => s.data.g.as_slice(),
    };
    (sc.controller).torque(q, v, &s.q_cmd, &s.v_cmd, ff, &mut s.tau_raw);
}

/// (τ_raw, q, v, q_cmd, motors) ⇒ τ (held over the step) and `bounds`: each joint's drive's
/// ([`super::JointDrive::actuate`]): under the PD τ_raw clipped to the limits, and under
/// `motors` to each motor's envelope at the joint's speed, r·η·bounds(r·q̇); under `drive`
/// stepper a stepper's joint gets what its torque–angle curve gives at the rotor's lag behind
/// the driver's microstep, r·η·T(r·q, r·q̇, θ_cmd), which is also its τ_raw (an open-loop
/// stepper asks for nothing else), and its reducer's Coulomb friction (the viscous losses are
/// in the joint's damping); under `drive` servo each servo is sent the goal of the frame at
/// time `t` (s) when it is new, and its joint gets what the servo's own loop gives on it,
/// τ_s·u' (its speed drag in the joint's damping). Every drive adds the joint's own Coulomb
/// friction ([`crate::model::Joint::friction`]; a stepper's reducer's and the joint's add).
#[inline]
pub fn actuation(sc: &Scenario, s: &mut Step, t: f64) {
    let Some(motors) = &sc.motors else {
        drives::actuate_without_motors(sc, s);
        return;
    };
    drives::send_goals(sc, s, t);
    for (i, (drive, motor)) in sc.drives.iter().zip(motors).enumerate() {
        drive.actuate(sc, s, i, motor.as_ref(), t);
    }
}

/// (q, v, q_cmd, v_cmd, τ, τ_raw, g) at step `k`, time `t` (s) ⇒ the [`Sample`] a recorder
/// gets, with the tool's position (forward kinematics) and the shape's target at `t`;
/// `intersecting` as [`Sample::intersecting`].
pub fn sample<'a>(sc: &Scenario, s: &'a mut Step, k: usize, t: f64, intersecting: &'a [bool]) -> Sample<'a> {
    let tool = frame_position(&sc.model, &s.state.q, sc.tool_frame);
    let target = sc.shape.as_ref().map(|shape| {
        shape.target.eval(t, &mut s.target, &mut s.target_rate);
        Vec3::from(s.target)
    });
    Sample {
        step: k,
        t,
        q: &s.state.q,
        v: &s.state.v,
        q_cmd: &s.q_cmd,
        v_cmd: &s.v_cmd,
        tau: &s.state.tau,
        tau_raw: &s.tau_raw,
        g: s.data.g.as_slice(),
        tool,
        target,
        intersecting,
    }
}

/// (M, C v + g, τ, q, v) ⇒ (q, v) at t + Δt: the discrete step at time `t` (s), with contact
/// under `self_collisions`. An error when the step cannot be solved (see
/// [`integrate_discrete`]).
#[inline]
pub fn integrate(sc: &Scenario, s: &mut Step, t: f64) -> Result<()> {
    match &mut s.contact {
        Some(contact) => contact.step(&sc.model, &mut s.data, &mut s.state, t),
        None => integrate_discrete(&sc.model, &mut s.data, &mut s.state),
    }
}

/// The step at time `t` (s): [`dynamics`], [`command`], [`controller`], [`actuation`],
/// [`integrate`] ⇒ (q, v) at t + Δt, as [`super::run`] takes it.
pub fn step(sc: &Scenario, s: &mut Step, t: f64) -> Result<()> {
    dynamics(sc, s);
    command(sc, s, t);
    controller(sc, s);
    actuation(sc, s, t);
    integrate(sc, s, t)
}
