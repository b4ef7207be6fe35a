//! The motor kinds, each in its own file: what it gives at a shaft speed (its envelope), its
//! checks, what a motors file gives of it (its `[[joint]]` fields) and what its plot and step
//! loss make of it. This file is the one registration point: a kind is an [`Envelope`]
//! variant, one arm in each of its methods, and one entry of [`KINDS`] (docs/motors.md;
//! ARCHITECTURE.md, "How to add a motor kind").
//!
//! ```text
//!   dc:      τ_m ∈ [τ_s(−1 − ω_m/ω₀), τ_s(1 − ω_m/ω₀)] ∩ [−τ_peak, τ_peak]
//!   stepper: |τ_m| ≤ curve(|ω_m|)   (linear between the points, zero past the last)
//! ```

mod dc;
mod stepper;

use serde::Deserialize;
use serde::de::{self, Deserializer, Visitor};

pub use stepper::{StepperLosses, Stepping};

/// What a motor gives at a shaft speed.
#[derive(Clone, Debug, PartialEq)]
pub enum Envelope {
    /// A voltage-limited DC motor or servo (four quadrants, IsaacLab's `DCMotor`).
    Dc {
        /// Stall torque τ_s (N·m at the shaft, > 0).
        stall_torque: f64,
        /// No-load speed ω₀ (rad/s at the shaft, > 0).
        no_load_speed: f64,
        /// The cap ±τ_peak (N·m, > 0; the stall torque unless given).
        peak_torque: f64,
    },
    /// An open-loop stepper's pull-out curve: (ω_m rad/s, τ N·m) points at the shaft, speeds
    /// ascending from 0, linear between them, zero past the last. Above it the stepper loses
    /// steps.
    Stepper {
        /// The points, at least one, the first at ω = 0.
        curve: Vec<[f64; 2]>,
    },
}

impl Envelope {
    /// The motor torque range [lo, hi] (N·m) at shaft speed `omega` (rad/s).
    #[inline]
    pub fn bounds(&self, omega: f64) -> (f64, f64) {
        match self {
            Envelope::Dc {
                stall_torque,
                no_load_speed,
                peak_torque,
            } => dc::bounds(*stall_torque, *no_load_speed, *peak_torque, omega),
            Envelope::Stepper { curve } => stepper::bounds(curve, omega),
        }
    }

    /// The most torque the motor gives at any speed (N·m): the peak for a DC motor, the
    /// curve's largest point for a stepper.
    pub fn max_torque(&self) -> f64 {
        match self {
            Envelope::Dc { peak_torque, .. } => *peak_torque,
            Envelope::Stepper { curve } => stepper::max_torque(curve),
        }
    }

    /// The shaft speeds (rad/s, ascending, both signs) where [`Envelope::bounds`] changes slope:
    /// between two of them both bounds are affine in ω (a DC motor's beyond the outermost too;
    /// a stepper's are zero there). A DC motor's are where its lines meet ±τ_peak,
    /// `ω₀(±1 ∓ τ_peak/τ_s)`; a stepper's, its curve's speeds on either side.
    pub fn kinks(&self) -> Vec<f64> {
        let mut kinks = match self {
            Envelope::Dc {
                stall_torque,
                no_load_speed,
                peak_torque,
            } => dc::kinks(*stall_torque, *no_load_speed, *peak_torque),
            Envelope::Stepper { curve } => stepper::kinks(curve),
        };
        kinks.sort_by(f64::total_cmp);
        kinks.dedup();
        kinks
    }

    /// The fastest the motor can turn its shaft while still giving torque in the direction of
    /// motion (rad/s): a DC motor's no-load speed ω₀, a stepper's last curve point (past it the
    /// envelope is zero).
    pub fn top_speed(&self) -> f64 {
        match self {
            Envelope::Dc { no_load_speed, .. } => *no_load_speed,
            Envelope::Stepper { curve } => stepper::top_speed(curve),
        }
    }

    /// `"dc"` or `"stepper"`: its name in a motors file and the summary.
    pub fn kind(&self) -> &'static str {
        match self {
            Envelope::Dc { .. } => dc::KIND.name,
            Envelope::Stepper { .. } => stepper::KIND.name,
        }
    }

    /// Whether torque beyond the envelope loses steps (an open-loop stepper: the summary's
    /// step loss, and what `drive = "stepper"` drives) rather than being clipped.
    pub fn loses_steps(&self) -> bool {
        matches!(self, Envelope::Stepper { .. })
    }

    /// What the motor plot says where the motor has no continuous rating, if anything.
    pub fn no_continuous_note(&self) -> Option<&'static str> {
        match self {
            Envelope::Dc { .. } => None,
            Envelope::Stepper { .. } => Some(stepper::NO_CONTINUOUS),
        }
    }

    /// Scales every torque of the envelope by `factor` (a sweep's `stall_torque_scale`).
    pub fn scale_torque(&mut self, factor: f64) {
        match self {
            Envelope::Dc {
                stall_torque,
                peak_torque,
                ..
            } => {
                *stall_torque *= factor;
                *peak_torque *= factor;
            }
            Envelope::Stepper { curve } => curve.iter_mut().for_each(|p| p[1] *= factor),
        }
    }

    /// Whether its figures make an envelope: a DC motor's stall torque, no-load speed and peak
    /// above 0, a stepper's curve of at least two points, from ω = 0, its speeds ascending and
    /// its torques ≥ 0. The error says which figure.
    pub fn check(&self) -> Result<(), String> {
        match self {
            Envelope::Dc {
                stall_torque,
                no_load_speed,
                peak_torque,
            } => dc::check(*stall_torque, *no_load_speed, *peak_torque),
            Envelope::Stepper { curve } => stepper::check(curve),
        }
    }
}

/// What a kind reads from its fields: the envelope, and for an open-loop drive its rotor.
pub type KindMotor = (Envelope, Option<Stepping>);

/// A motor kind as a motors file names it: its name, its `[[joint]]` fields (beyond those
/// every entry has) and how they read into an envelope and, for an open-loop drive, a rotor.
#[derive(Clone, Copy)]
pub struct Kind {
    /// Its `kind = "…"` word.
    pub name: &'static str,
    /// Its own fields, as its serde struct declares them.
    pub fields: fn() -> &'static [&'static str],
    /// Its fields (a JSON object of them alone, without `kind`) read by its serde struct and
    /// checked: its envelope and stepping, or the error in the file's words.
    pub read: fn(serde_json::Value) -> Result<KindMotor, String>,
    /// Whether its fields (a JSON object of some of them) have their types: said of the file,
    /// before the entries are paired with joints, in serde's words.
    pub types: fn(serde_json::Value) -> Result<(), String>,
    /// Its words for a field that is another kind's.
    pub has_no: fn(&str) -> String,
}

/// Every kind a motors file takes: the one registration point for reading them.
pub const KINDS: [Kind; 2] = [dc::KIND, stepper::KIND];

/// The kind named `name`, or the error in the file's words.
pub fn kind(name: &str) -> Result<&'static Kind, String> {
    KINDS.iter().find(|k| k.name == name).ok_or_else(|| {
        let names: Vec<String> = KINDS.iter().map(|k| format!("\"{}\"", k.name)).collect();
        let (last, rest) = names.split_last().expect("at least one kind");
        let list = if rest.is_empty() {
            last.clone()
        } else {
            format!("{} or {last}", rest.join(", "))
        };
        format!("kind \"{}\" is not {list}", crate::error::escape_controls(name))
    })
}

/// `value` read as `T` (a kind's serde struct), the error in the file's words.
fn read_as<T: for<'de> Deserialize<'de>>(value: serde_json::Value) -> Result<T, String> {
    serde_json::from_value(value).map_err(|e| crate::error::file_words(&e.to_string()))
}

/// The field names a serde struct declares (what its derived `Deserialize` hands to
/// `deserialize_struct`): a kind's fields, declared once, in its struct.
fn fields_of<T: for<'de> Deserialize<'de>>() -> &'static [&'static str] {
    let mut fields: &'static [&'static str] = &[];
    let _ = T::deserialize(Introspect(&mut fields));
    fields
}

/// A deserializer that only records the fields of the struct asked of it.
struct Introspect<'a>(&'a mut &'static [&'static str]);

impl<'de> Deserializer<'de> for Introspect<'_> {
    type Error = de::value::Error;

    fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, Self::Error> {
        Err(de::Error::custom("not a struct"))
    }

    fn deserialize_struct<V: Visitor<'de>>(
        self,
        _: &'static str,
        fields: &'static [&'static str],
        _: V,
    ) -> Result<V::Value, Self::Error> {
        *self.0 = fields;
        Err(de::Error::custom("fields recorded"))
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
        option unit unit_struct newtype_struct seq tuple tuple_struct map enum identifier
        ignored_any
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each kind's fields are its struct's, none shared between two kinds (a field names one
    /// kind's figure), and an unknown kind is refused naming them all.
    #[test]
    fn kinds_declare_their_fields_once() {
        assert_eq!((KINDS[0].fields)(), ["stall_torque", "no_load_speed", "peak_torque"]);
        assert!((KINDS[1].fields)().contains(&"curve") && (KINDS[1].fields)().contains(&"step_angle"));
        for a in KINDS {
            for b in KINDS.iter().filter(|b| b.name != a.name) {
                assert!(
                    (a.fields)().iter().all(|f| !(b.fields)().contains(f)),
                    "{} {}",
                    a.name,
                    b.name
                );
            }
        }
        assert_eq!(
            kind("servo").err().unwrap(),
            "kind \"servo\" is not \"dc\" or \"stepper\""
        );
        assert_eq!(kind("dc").unwrap().name, "dc");
    }
}
