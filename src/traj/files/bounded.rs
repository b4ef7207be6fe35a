//! Lists read under a cap on their number of elements, checked as each element comes (a
//! decoder of ROS messages takes a list's claimed length from the file): a message of 32 million
//! one-letter joint names, 24 kB compressed, is refused at the 257th name instead of taking
//! gigabytes. Each is a serde `deserialize_with` for the list fields of the messages
//! ([`super::ros`]); the caps are [`MAX_MOVING_JOINTS`] joints (and values per point) and
//! [`MAX_TRAJECTORY_POINTS`] points (docs/development.md, Caps). A YAML or JSON document is read
//! into its format's tree under a cap on its number of values ([`tree`], [`MAX_TEXT_VALUES`]),
//! counted as each value is built: a YAML alias repeats a list without its text, and a text of
//! one-letter values costs about thirty times itself as a tree.

use std::cell::Cell;
use std::fmt;
use std::marker::PhantomData;

use serde::de::{
    Deserialize, DeserializeSeed, Deserializer, EnumAccess, Error, MapAccess, SeqAccess, VariantAccess, Visitor,
};

use crate::input::{MAX_MOVING_JOINTS, MAX_TEXT_VALUES, MAX_TRAJECTORY_POINTS};

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

/// A format's tree of values (serde_json's, serde_norway's), built by [`tree`].
pub trait Tree: Sized {
    /// Null (`~`, `null`, an empty value).
    fn null() -> Self;
    /// A boolean.
    fn bool(b: bool) -> Self;
    /// A signed integer.
    fn int(i: i64) -> Self;
    /// An unsigned integer.
    fn uint(u: u64) -> Self;
    /// A float (a format without non-finite numbers gives null).
    fn float(x: f64) -> Self;
    /// A string.
    fn string(s: String) -> Self;
    /// A sequence.
    fn seq(items: Vec<Self>) -> Self;
    /// A mapping's entries, in order, or what is wrong with them (a key given twice: one of
    /// them would be dropped unsaid; a key the format does not take).
    fn map(entries: Vec<(Self, Self)>) -> Result<Self, String>;
    /// A tagged value (YAML's `!tag value`; `None` where the format has no tags).
    fn tagged(tag: String, value: Self) -> Option<Self>;
}

/// The values counted so far against [`MAX_TEXT_VALUES`].
#[derive(Debug, Default)]
pub struct Budget(Cell<usize>);

impl Budget {
    /// One more value, or the refusal once [`MAX_TEXT_VALUES`] are spent.
    fn spend<E: Error>(&self) -> Result<(), E> {
        self.0.set(self.0.get() + 1);
        match self.refusal() {
            Some(refusal) => Err(E::custom(refusal)),
            None => Ok(()),
        }
    }

    /// The refusal, once more than [`MAX_TEXT_VALUES`] were spent (the parser's error then
    /// wraps it in its own words: this is the cause).
    pub fn refusal(&self) -> Option<String> {
        (self.0.get() > MAX_TEXT_VALUES).then(|| {
            format!(
                "more than {MAX_TEXT_VALUES} values (YAML aliases counted where they repeat a value; docs/development.md, Caps)"
            )
        })
    }
}

/// The tree `deserializer` holds, each of its values counted against `budget` as it is built
/// (one budget for a file's documents).
pub fn tree<'de, D: Deserializer<'de>, T: Tree>(deserializer: D, budget: &Budget) -> Result<T, D::Error> {
    Counted(budget, PhantomData).deserialize(deserializer)
}

/// A value built under a [`Budget`]: the seed and the visitor.
struct Counted<'b, T>(&'b Budget, PhantomData<T>);

impl<T> Clone for Counted<'_, T> {
    fn clone(&self) -> Self {
        Counted(self.0, PhantomData)
    }
}

impl<'de, T: Tree> DeserializeSeed<'de> for Counted<'_, T> {
    type Value = T;

    fn deserialize<D: Deserializer<'de>>(self, deserializer: D) -> Result<T, D::Error> {
        self.0.spend()?;
        deserializer.deserialize_any(self)
    }
}

impl<'de, T: Tree> Visitor<'de> for Counted<'_, T> {
    type Value = T;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("any value")
    }

    fn visit_bool<E: Error>(self, b: bool) -> Result<T, E> {
        Ok(T::bool(b))
    }

    fn visit_i64<E: Error>(self, i: i64) -> Result<T, E> {
        Ok(T::int(i))
    }

    fn visit_u64<E: Error>(self, u: u64) -> Result<T, E> {
        Ok(T::uint(u))
    }

    fn visit_f64<E: Error>(self, x: f64) -> Result<T, E> {
        Ok(T::float(x))
    }

    fn visit_str<E: Error>(self, s: &str) -> Result<T, E> {
        Ok(T::string(s.to_owned()))
    }

    fn visit_string<E: Error>(self, s: String) -> Result<T, E> {
        Ok(T::string(s))
    }

    fn visit_unit<E: Error>(self) -> Result<T, E> {
        Ok(T::null())
    }

    fn visit_none<E: Error>(self) -> Result<T, E> {
        Ok(T::null())
    }

    fn visit_some<D: Deserializer<'de>>(self, deserializer: D) -> Result<T, D::Error> {
        deserializer.deserialize_any(self)
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<T, A::Error> {
        // what a claim reserves is bounded: the rest grows with the values there are
        let mut items = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(1024));
        while let Some(item) = seq.next_element_seed(self.clone())? {
            items.push(item);
        }
        Ok(T::seq(items))
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<T, A::Error> {
        let mut entries = Vec::with_capacity(map.size_hint().unwrap_or(0).min(1024));
        while let Some(key) = map.next_key_seed(self.clone())? {
            entries.push((key, map.next_value_seed(self.clone())?));
        }
        T::map(entries).map_err(A::Error::custom)
    }

    fn visit_enum<A: EnumAccess<'de>>(self, data: A) -> Result<T, A::Error> {
        let (tag, contents) = data.variant::<String>()?;
        let value = contents.newtype_variant_seed(self)?;
        T::tagged(tag, value).ok_or_else(|| A::Error::custom("a tagged value"))
    }
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
