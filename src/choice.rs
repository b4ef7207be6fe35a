//! The words a user names the values of a configuration enum by (`--drive stepper`,
//! `drive="stepper"`, a summary's `"stepper"`): each enum lists them once ([`Choice`]), and the
//! option that takes it, the parsing and the summary read them from there.

/// An enum whose values a user names by words. Inside the crate, `choice_words!` writes the two
/// lists from one: `choice_words!(DriveMode { Pd => "pd", Stepper => "stepper" })`.
pub trait Choice: Copy + PartialEq + Sized + 'static {
    /// The values a word names, in the order an option lists them.
    const VALUES: &'static [Self];
    /// Their words, in the order of [`Choice::VALUES`].
    const WORDS: &'static [&'static str];

    /// The word of `self`; empty for a value no word names (a default the user cannot ask
    /// for by name, as [`crate::geometry::PairFilter::NonAdjacent`]).
    fn word(self) -> &'static str {
        (Self::VALUES.iter().position(|v| *v == self)).map_or("", |i| Self::WORDS[i])
    }

    /// The value `word` names.
    fn from_word(word: &str) -> Option<Self> {
        (Self::WORDS.iter().position(|w| *w == word)).map(|i| Self::VALUES[i])
    }
}

/// Implements [`Choice`] for an enum from one list of `Variant => "word"`.
macro_rules! choice_words {
    ($ty:ident { $($variant:ident => $word:literal),+ $(,)? }) => {
        impl $crate::choice::Choice for $ty {
            const VALUES: &'static [Self] = &[$($ty::$variant),+];
            const WORDS: &'static [&'static str] = &[$($word),+];
        }
    };
}
pub(crate) use choice_words;

#[cfg(test)]
mod tests {
    use super::Choice;

    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Tone {
        Low,
        High,
        Unnamed,
    }
    super::choice_words!(Tone { Low => "low", High => "high" });

    #[test]
    fn a_word_names_its_value_and_back() {
        assert_eq!(Tone::WORDS, ["low", "high"]);
        assert_eq!((Tone::High.word(), Tone::Unnamed.word()), ("high", ""));
        assert_eq!(Tone::from_word("low"), Some(Tone::Low));
        assert_eq!(Tone::from_word("Low"), None);
    }
}
