//! A closed set of choices, each with the name a step, a panel or a message uses for it.
//!
//! Methods of smoothing and parameterization, boundary shapes, quantities and the command line's
//! local steps all read as `NAME` in `process` steps and back. [`Named`] gives each one table,
//! [`Named::ALL`], and derives the rest from it: the name of a value, the value of a name, and
//! the list of names for a message. A name is unique within its set.

/// A set of values with a name each (see the module doc).
pub trait Named: Copy + PartialEq + Sized + 'static {
    /// Every value, with its name, in the order menus and messages list them.
    const ALL: &'static [(Self, &'static str)];

    /// Its name ("" for a value missing from [`Named::ALL`], which is a bug).
    fn name(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(value, _)| *value == self)
            .map_or("", |(_, name)| name)
    }

    /// The value called `name` (any case), if there is one.
    fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .iter()
            .find(|(_, n)| n.eq_ignore_ascii_case(name))
            .map(|(value, _)| *value)
    }

    /// Every name, joined by `|` (for a message saying what is expected).
    fn names() -> String {
        Self::ALL
            .iter()
            .map(|(_, name)| *name)
            .collect::<Vec<_>>()
            .join("|")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Shade {
        Light,
        Dark,
    }

    impl Named for Shade {
        const ALL: &'static [(Self, &'static str)] =
            &[(Shade::Light, "light"), (Shade::Dark, "dark")];
    }

    #[test]
    fn names_and_values_round_trip() {
        for &(value, name) in Shade::ALL {
            assert_eq!(value.name(), name);
            assert_eq!(Shade::from_name(name), Some(value));
            assert_eq!(Shade::from_name(&name.to_uppercase()), Some(value));
        }
        assert_eq!(Shade::from_name("grey"), None);
        assert_eq!(Shade::names(), "light|dark");
    }
}
