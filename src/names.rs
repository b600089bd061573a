//! Named choices: enums whose values the command line, scene files, Python and reports
//! spell as words (`Window::Hann` is `hann`). One mechanism for all of them: the
//! [`named_enum!`](crate::named_enum) macro writes `ALL`, `name`, `from_name`, `Display`
//! and the [`Named`] trait from one table of variants and names.

use crate::error::{clip, Error, Result};

/// An enum of unit variants with one name each.
pub trait Named: Copy + 'static {
    /// What a value is, for messages (`"window"`).
    const WHAT: &'static str;
    /// Every value, in the order of [`Named::names`].
    fn all() -> &'static [Self];
    /// The value's name.
    fn name(self) -> &'static str;
    /// Every name, in the order of [`Named::all`].
    fn names() -> Vec<&'static str> {
        Self::all().iter().map(|v| v.name()).collect()
    }
}

/// The value of `T` named `name`. Error: another name (the message lists the names).
pub fn from_name<T: Named>(name: &str) -> Result<T> {
    T::all()
        .iter()
        .copied()
        .find(|v| v.name() == name)
        .ok_or_else(|| {
            Error::invalid(
                T::WHAT,
                clip(name),
                format!("one of {}", T::names().join(", ")),
            )
        })
}

/// Names the unit variants of an enum: `named_enum!(Window, "window", { None => "none",
/// Hann => "hann" })` gives `Window::ALL` (an array), `name`, `from_name` (the error lists
/// the names), `Display` and [`Named`].
#[macro_export]
macro_rules! named_enum {
    ($ty:ident, $what:literal, { $($variant:ident => $name:literal),+ $(,)? }) => {
        impl $ty {
            /// Every value, in the order of their names.
            pub const ALL: [$ty; { [$(stringify!($variant)),+].len() }] = [$($ty::$variant),+];

            /// The name the command line, scene files, Python and reports use.
            pub fn name(self) -> &'static str {
                match self {
                    $($ty::$variant => $name),+
                }
            }

            /// The value named `name` ([`Self::name`]). Error: another name (the message
            /// lists the names).
            pub fn from_name(name: &str) -> $crate::Result<Self> {
                $crate::names::from_name(name)
            }
        }

        impl $crate::names::Named for $ty {
            const WHAT: &'static str = $what;
            fn all() -> &'static [Self] {
                &Self::ALL
            }
            fn name(self) -> &'static str {
                $ty::name(self)
            }
        }

        impl std::fmt::Display for $ty {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.name())
            }
        }
    };
}

#[cfg(test)]
mod tests {
    /// A choice of two.
    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Pair {
        First,
        Second,
    }

    named_enum!(Pair, "pair", { First => "first", Second => "second-one" });

    #[test]
    fn names_round_trip_and_unknown_names_list_the_choices() {
        assert_eq!(Pair::ALL, [Pair::First, Pair::Second]);
        for p in Pair::ALL {
            assert_eq!(Pair::from_name(p.name()).unwrap(), p);
            assert_eq!(p.to_string(), p.name());
        }
        let e = Pair::from_name("third").unwrap_err().to_string();
        assert_eq!(e, "invalid pair = third: one of first, second-one");
    }
}
