//! Pappus's own checks: the mesh validated after every edit and the operations' internal
//! assertions. On in the dev profile (debug assertions) and, in any profile, with the
//! `checked` cargo feature, which changes no dependency's build: `cargo test --release
//! --features checked` (the README's test command) runs the tests with every check on the
//! dependencies `cargo build --release` built, instead of building them all again in the test
//! profile. Off in the release editor, where a check would cost the user every edit's
//! validation.

/// Whether this build checks its own work as it goes (see the module doc).
pub const CHECKED: bool = cfg!(any(debug_assertions, feature = "checked"));

/// `assert!` when [`CHECKED`]: a `debug_assert!` that the `checked` feature keeps in release.
macro_rules! checked_assert {
    ($($arguments:tt)*) => {
        if $crate::checks::CHECKED {
            assert!($($arguments)*);
        }
    };
}

/// `assert_eq!` when [`CHECKED`] (see [`checked_assert!`]).
macro_rules! checked_assert_eq {
    ($($arguments:tt)*) => {
        if $crate::checks::CHECKED {
            assert_eq!($($arguments)*);
        }
    };
}

pub(crate) use {checked_assert, checked_assert_eq};

/// The tests run with Pappus's own checks: in the dev profile, or in release with the `checked`
/// feature. A release test build without it would check less, so it does not compile.
#[cfg(test)]
const _: () = assert!(
    CHECKED,
    "run the tests as `cargo test --release --features checked` (or `cargo test`)"
);
