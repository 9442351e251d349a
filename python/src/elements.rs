//! Numbers written as a step's text, so that a method that builds a step (`deform`) and a
//! keyword `run` reads through its parameter's text reader agree with the command line.

/// A Python float as a step writes it (the shortest text that reads back to the same value).
pub(crate) fn number(x: f64) -> String {
    format!("{x}")
}
