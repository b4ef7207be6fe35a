//! Lists read under a cap on their number of elements, checked as each element comes (a
//! decoder of ROS messages takes a list's claimed length from the file): a message of 32 million
//! one-letter joint names, 24 kB compressed, is refused at the 257th name instead of taking
//! gigabytes. Each is a serde `deserialize_with` for the list fields of the messages
//! ([`super::ros`]); the caps are [`MAX_MOVING_JOINTS`] joints (and values per point) and
//! [`MAX_TRAJECTORY_POINTS`] points (docs/development.md, Caps).

use std::fmt;
use std::marker::PhantomData;

use serde::de::{Deserialize, Deserializer, Error, SeqAccess, Visitor};

use crate::input::{MAX_MOVING_JOINTS, MAX_TRAJECTORY_POINTS};

/// A list of at most `max` elements; `what` names them in the refusal.
struct AtMost<T> {
    max: usize,
    what: &'static str,
    element: PhantomData<T>,
}

impl<'de, T: Deserialize<'de>> Visitor<'de> for AtMost<T> {
    type Value = Vec<T>;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "a list of at most {} {}", self.max, self.what)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<T>, A::Error> {
        let too_many = || {
            A::Error::custom(format!(
                "more than {} {} in one list (docs/development.md, Caps)",
                self.max, self.what
            ))
        };
        if seq.size_hint().is_some_and(|n| n > self.max) {
            return Err(too_many());
        }
        // what a claim reserves is bounded too: the rest grows with the elements there are
        let mut out = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(1024));
        while let Some(element) = seq.next_element()? {
            if out.len() == self.max {
                return Err(too_many());
            }
            out.push(element);
        }
        Ok(out)
    }
}

fn at_most<'de, D: Deserializer<'de>, T: Deserialize<'de>>(
    deserializer: D,
    max: usize,
    what: &'static str,
) -> Result<Vec<T>, D::Error> {
    deserializer.deserialize_seq(AtMost {
        max,
        what,
        element: PhantomData,
    })
}

/// A list of joint names: at most [`MAX_MOVING_JOINTS`].
pub fn names<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Vec<String>, D::Error> {
    at_most(deserializer, MAX_MOVING_JOINTS, "joint names")
}

/// A list of values, one per joint: at most [`MAX_MOVING_JOINTS`].
pub fn values<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Vec<f64>, D::Error> {
    at_most(deserializer, MAX_MOVING_JOINTS, "values")
}

/// A trajectory's points: at most [`MAX_TRAJECTORY_POINTS`].
pub fn points<'de, D: Deserializer<'de>, T: Deserialize<'de>>(deserializer: D) -> Result<Vec<T>, D::Error> {
    at_most(deserializer, MAX_TRAJECTORY_POINTS, "points")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, serde::Deserialize)]
    struct Listed {
        #[serde(deserialize_with = "names")]
        names: Vec<String>,
    }

    #[test]
    fn a_list_past_its_cap_is_refused_at_the_element_past_it() {
        let list = |n: usize| format!("{{\"names\": [{}]}}", vec!["\"a\""; n].join(","));
        let read = |n| serde_json::from_str::<Listed>(&list(n));
        assert_eq!(read(MAX_MOVING_JOINTS).unwrap().names.len(), MAX_MOVING_JOINTS);
        let e = read(MAX_MOVING_JOINTS + 1).unwrap_err().to_string();
        assert!(e.starts_with("more than 256 joint names in one list"), "{e}");
    }
}
