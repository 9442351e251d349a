//! What a reader read past, counted, for the note every front end shows when a file opens:
//! `"skipped: 1 camera(s), 2 line primitive(s)"`.

use std::borrow::Cow;

/// Counts of what a reader read past, by what it is in a person's words
/// (`"line primitive(s)"`), in order of first appearance.
#[derive(Default, Clone, Debug)]
pub(super) struct Skipped(Vec<(Cow<'static, str>, usize)>);

impl Skipped {
    /// Counts `n` more of `what`.
    pub fn count(&mut self, what: impl Into<Cow<'static, str>>, n: usize) {
        if n == 0 {
            return;
        }
        let what = what.into();
        match self.0.iter_mut().find(|(w, _)| *w == what) {
            Some((_, count)) => *count += n,
            None => self.0.push((what, n)),
        }
    }

    /// Adds another's counts.
    pub fn add(&mut self, other: &Skipped) {
        for (what, n) in &other.0 {
            self.count(what.clone(), *n);
        }
    }

    /// The note for the soup: `"skipped: 1 camera(s), 2 line primitive(s)"`; `None` when
    /// nothing was.
    pub fn note(&self) -> Option<String> {
        let phrases: Vec<String> = self
            .0
            .iter()
            .map(|(what, n)| format!("{n} {what}"))
            .collect();
        (!phrases.is_empty()).then(|| format!("skipped: {}", phrases.join(", ")))
    }
}
