//! Smart servos as they drive themselves (docs/motors.md, "Smart servos"): a Feetech STS or
//! Dynamixel X servo runs its own position loop on the goal it is sent, its output a PWM duty u
//! of its supply within its torque-limit register, and protects itself when its output stays
//! high too long. A pure model: an immutable [`ServoSpec`], one [`ServoState`] per servo,
//! nothing allocated per step.
//!
//! Per control step, with the goal g sent at the trajectory's rate (held between frames) and
//! the output position q, both in encoder counts (`counts_per_rev` a turn), e = g − q:
//!
//! ```text
//!   u   = clamp(k·(P·e + D·ė + I·∫e dt), ±u_lim)   the duty asked (ė in counts/ms)
//!   u'  = protect(u)                               the duty given (below)
//!   τ   = τ_s·u' − c·q̇,   c = τ_s/ω₀               a DC motor at duty u' (at the output)
//!   i   = τ·ω₀/V                                   its current (K = V/ω₀ at the output)
//! ```
//!
//! τ_s and ω₀ the stall torque and no-load speed at the supply V. [`ServoSpec::step`] gives
//! τ_s·u'; the speed drag −c·q̇ is the joint's viscous damping c ([`ServoSpec::drag`]), which
//! the integrator takes implicitly (docs/model.md): taken explicitly it is unstable on a light
//! joint (c·Δt/I > 2: the SO-101's gripper, I ≈ 2·10⁻⁵ kg·m², c = 0.35 N·m·s/rad at 5 kHz).
//!
//! The protection, after the manufacturers' registers:
//!
//! * Feetech: the duty above its overload torque for its protection time limits it to its
//!   protective torque, until the loop asks for less than the overload torque again; a current
//!   above its protection current for its over-current time turns the output off.
//! * Dynamixel (its Shutdown register's Overload bit): the output held at its PWM limit for the
//!   overload time turns the torque off; only a reboot brings it back.

/// The registers of a smart servo's position loop and protection and its motor at its supply,
/// in SI units at the output and shares of the full duty.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ServoSpec {
    /// Encoder counts per output turn.
    pub counts_per_rev: f64,
    /// The position loop's P register.
    pub p: f64,
    /// Its D register (per count per millisecond).
    pub d: f64,
    /// Its I register (per count·second).
    pub i: f64,
    /// k: the duty one unit of P gives per count of error (the registers' scale).
    pub duty_per_count: f64,
    /// u_lim, the torque-limit register: the largest duty (share of the supply, in (0, 1]).
    pub torque_limit: f64,
    /// τ_s: the stall torque at the output at the supply (N·m).
    pub stall_torque: f64,
    /// ω₀: the no-load speed at the output at the supply (rad/s).
    pub no_load_speed: f64,
    /// V: the supply (V).
    pub supply: f64,
    /// How it protects itself.
    pub protection: Protection,
}

/// A smart servo's self-protection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Protection {
    /// Feetech STS: Overload_Torque, Protection_Time, Protective_Torque, Protection_Current and
    /// Over_Current_Protection_Time.
    Feetech {
        /// The duty above which the overload timer runs (share).
        overload: f64,
        /// How long above it trips the protection (s).
        time: f64,
        /// The duty it is limited to once tripped (share).
        protective: f64,
        /// The current above which the over-current timer runs (A).
        current: f64,
        /// How long above it turns the output off (s).
        current_time: f64,
    },
    /// Dynamixel X: the Overload Error of its Shutdown register: the output at its PWM limit
    /// for `time` s turns the torque off.
    Dynamixel {
        /// How long at the limit shuts it down (s).
        time: f64,
    },
}

/// What tripped a servo's protection.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TripKind {
    /// Feetech's overload protection: the output limited to its protective torque.
    Overload,
    /// Feetech's over-current protection: the output off.
    OverCurrent,
    /// Dynamixel's overload shutdown: the torque off until a reboot.
    Shutdown,
}

/// When and how a servo's protection acted.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Trip {
    /// Which protection.
    pub kind: TripKind,
    /// When it acted (s).
    pub t: f64,
    /// The largest torque at the output over the time that tripped it (N·m).
    pub torque: f64,
    /// How long the output was above the threshold before it acted (s).
    pub duration: f64,
}

/// One servo's state over a run: its goal, its loop's memory and its protection's timers.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ServoState {
    /// The goal it was last sent (rad at the output).
    pub goal: f64,
    /// The goal's frame (the goal is sent at the trajectory's rate); `None` before the first.
    pub frame: Option<u64>,
    /// The previous step's error (counts).
    last_error: Option<f64>,
    /// ∫e dt (count·s).
    integral: f64,
    /// Time the duty has been above the overload threshold (s).
    over: f64,
    /// Time the current has been above the protection current (s).
    over_current: f64,
    /// The largest output torque while above the threshold (N·m).
    over_torque: f64,
    /// Whether the overload protection is limiting the output now.
    pub limited: bool,
    /// Whether the output is off (over-current, or a Dynamixel shutdown).
    pub off: bool,
    /// The first trip.
    pub trip: Option<Trip>,
    /// The largest duty the loop asked for (share).
    pub max_duty: f64,
    /// The duty the loop asked for at the last step (share).
    pub asked: f64,
}

impl ServoState {
    /// Sends the goal of frame `frame` (`goal` rad at the output) if that frame is new: the
    /// servo holds a goal until the next frame's (the trajectory's rate).
    #[inline]
    pub fn send(&mut self, frame: u64, goal: f64) {
        if self.frame != Some(frame) {
            self.frame = Some(frame);
            self.goal = goal;
        }
    }
}

impl ServoSpec {
    /// c = τ_s/ω₀: the motor's speed drag at the output (N·m·s/rad), the joint's viscous
    /// damping under the servo (taken implicitly).
    pub fn drag(&self) -> f64 {
        self.stall_torque / self.no_load_speed
    }

    /// The duty the loop asks for at the goal held in `s` and the position `q` (rad at the
    /// output), its memory updated over a step of `dt` s, within the torque limit.
    #[inline]
    pub fn duty(&self, s: &mut ServoState, q: f64, dt: f64) -> f64 {
        let counts = self.counts_per_rev / std::f64::consts::TAU;
        let e = (s.goal * counts).round() - (q * counts).round();
        let rate = s.last_error.map_or(0.0, |last| (e - last) / (dt * 1e3));
        s.last_error = Some(e);
        s.integral += e * dt;
        let u = self.duty_per_count * (self.p * e + self.d * rate + self.i * s.integral);
        u.clamp(-self.torque_limit, self.torque_limit)
    }

    /// One control step of `dt` s at time `t` (s): the loop's duty at position `q` and speed
    /// `qd` (rad, rad/s at the output), the protection's answer, and the torque it gives at
    /// zero speed, τ_s·u' (N·m at the output; the drag −c·q̇ is the joint's damping).
    #[inline]
    pub fn step(&self, s: &mut ServoState, q: f64, qd: f64, t: f64, dt: f64) -> f64 {
        let asked = self.duty(s, q, dt);
        let torque = |u: f64| self.stall_torque * u - self.drag() * qd;
        let current = torque(asked) * self.no_load_speed / self.supply;
        let given = self.protect(s, asked, current, torque(asked), t, dt);
        self.stall_torque * given
    }

    /// The protection over a step of `dt` s at time `t`: `asked` the loop's duty, `current` the
    /// motor's (A), `torque` the output's (N·m); returns the duty the servo gives. A timer acts at
    /// the step that brings it to its time (within half a step: the sum of the steps' Δt).
    fn protect(&self, s: &mut ServoState, asked: f64, current: f64, torque: f64, t: f64, dt: f64) -> f64 {
        s.max_duty = s.max_duty.max(asked.abs());
        s.asked = asked;
        if s.off {
            return 0.0;
        }
        match self.protection {
            Protection::Feetech {
                overload,
                time,
                protective,
                current: most,
                current_time,
            } => {
                s.over_current = if current.abs() > most { s.over_current + dt } else { 0.0 };
                if s.over_current + 0.5 * dt >= current_time {
                    return s.shut(TripKind::OverCurrent, t, torque.abs(), s.over_current);
                }
                if asked.abs() > overload {
                    s.over += dt;
                    s.over_torque = s.over_torque.max(torque.abs());
                    if s.over + 0.5 * dt >= time && !s.limited {
                        s.limited = true;
                        s.trip.get_or_insert(Trip {
                            kind: TripKind::Overload,
                            t,
                            torque: s.over_torque,
                            duration: s.over,
                        });
                    }
                } else {
                    (s.over, s.over_torque, s.limited) = (0.0, 0.0, false);
                }
                match s.limited {
                    true => asked.clamp(-protective, protective),
                    false => asked,
                }
            }
            Protection::Dynamixel { time } => {
                if asked.abs() >= self.torque_limit * (1.0 - 1e-12) {
                    s.over += dt;
                    s.over_torque = s.over_torque.max(torque.abs());
                    if s.over + 0.5 * dt >= time {
                        return s.shut(TripKind::Shutdown, t, s.over_torque, s.over);
                    }
                } else {
                    (s.over, s.over_torque) = (0.0, 0.0);
                }
                asked
            }
        }
    }

    /// Whether its figures make a servo: counts, scale, torque, speed and supply finite and
    /// positive, gains finite and ≥ 0, the torque limit and the protection's shares in (0, 1], its
    /// times and current > 0. The error names the register.
    pub fn check(&self) -> Result<(), String> {
        let share = |name: &str, x: f64| match x > 0.0 && x <= 1.0 {
            true => Ok(()),
            false => Err(format!("{name} {x} must be in (0, 1]")),
        };
        let positive = |name: &str, x: f64| match x.is_finite() && x > 0.0 {
            true => Ok(()),
            false => Err(format!("{name} {x} must be > 0")),
        };
        positive("counts_per_rev", self.counts_per_rev)?;
        positive("duty_per_count", self.duty_per_count)?;
        positive("stall_torque", self.stall_torque)?;
        positive("no_load_speed", self.no_load_speed)?;
        positive("supply", self.supply)?;
        for (name, x) in [("p", self.p), ("d", self.d), ("i", self.i)] {
            if !(x.is_finite() && x >= 0.0) {
                return Err(format!("{name} {x} must be ≥ 0"));
            }
        }
        share("torque_limit", self.torque_limit)?;
        match self.protection {
            Protection::Feetech {
                overload,
                time,
                protective,
                current,
                current_time,
            } => {
                share("overload_torque", overload)?;
                share("protective_torque", protective)?;
                positive("protection_time", time)?;
                positive("protection_current", current)?;
                positive("over_current_time", current_time)
            }
            Protection::Dynamixel { time } => positive("overload_time", time),
        }
    }
}

impl ServoState {
    /// Turns the output off for good, the first trip recorded; the duty given, 0.
    fn shut(&mut self, kind: TripKind, t: f64, torque: f64, duration: f64) -> f64 {
        self.off = true;
        self.trip.get_or_insert(Trip {
            kind,
            t,
            torque,
            duration,
        });
        0.0
    }
}

#[cfg(test)]
mod tests;
