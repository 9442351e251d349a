//! The log's messages in the editor: a `tracing` layer ([`layer`], given to Bevy's
//! `LogPlugin` by [`super::capture_layer`]) that keeps the last [`LogMessages::CAPACITY`] messages for the Log section,
//! which shows those at or above the level its switch is set to.
//!
//! What reaches the layer is what the `LogPlugin`'s filter lets through: Bevy's default (info
//! and above), `RUST_LOG` where it is set, and [`LAB_TARGET`] at every level, so that a lab's
//! operations (`trace!(target: "lab", …)`, as `examples/lab/` writes what it touched) are read
//! in the panel without setting anything.

use std::collections::VecDeque;
use std::fmt::Write as _;
use std::sync::{Arc, Mutex};

use bevy::log::tracing::field::{Field, Visit};
use bevy::log::tracing::{Event, Level, Subscriber};
use bevy::log::tracing_subscriber::Layer;
use bevy::log::tracing_subscriber::layer::Context;
use bevy::log::{BoxedLayer, DEFAULT_FILTER};

/// The log target a lab's operations write to; the editor keeps its messages at every level.
pub const LAB_TARGET: &str = "lab";

/// The `LogPlugin` filter the editor runs with: Bevy's default, and [`LAB_TARGET`] at every
/// level.
pub fn log_filter() -> String {
    format!("{DEFAULT_FILTER}{LAB_TARGET}=trace")
}

/// One message of the log.
#[derive(Clone, Debug, PartialEq)]
pub struct LogMessage {
    /// Its level.
    pub level: Level,
    /// Its target (the module that wrote it, or the one it named: `lab`).
    pub target: String,
    /// Its text, with any fields after it (`name=value`).
    pub text: String,
}

/// The last messages, oldest first, shared between the layer (any thread) and the panel.
#[derive(Clone, Debug, Default)]
pub struct LogMessages(Arc<Mutex<VecDeque<LogMessage>>>);

impl LogMessages {
    /// How many messages are kept.
    pub const CAPACITY: usize = 500;

    /// Appends a message, dropping the oldest past the capacity.
    pub fn push(&self, message: LogMessage) {
        let mut messages = self
            .0
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        if messages.len() == Self::CAPACITY {
            messages.pop_front();
        }
        messages.push_back(message);
    }

    /// The newest `n` messages at `level` or more important that `keep` keeps, newest first.
    pub fn newest(
        &self,
        level: Level,
        n: usize,
        keep: impl Fn(&LogMessage) -> bool,
    ) -> Vec<LogMessage> {
        let messages = self
            .0
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        // `tracing` orders levels by verbosity: ERROR < WARN < … < TRACE.
        let shown = messages
            .iter()
            .rev()
            .filter(|m| m.level <= level && keep(m));
        shown.take(n).cloned().collect()
    }
}

/// The layer that keeps every message it is given in `messages`.
pub fn layer(messages: LogMessages) -> BoxedLayer {
    Box::new(Capture(messages))
}

/// Keeps every event it is given.
struct Capture(LogMessages);

impl<S: Subscriber> Layer<S> for Capture {
    fn on_event(&self, event: &Event<'_>, _: Context<'_, S>) {
        let mut text = Text::default();
        event.record(&mut text);
        let meta = event.metadata();
        self.0.push(LogMessage {
            level: *meta.level(),
            target: meta.target().to_string(),
            text: text.0,
        });
    }
}

/// An event's message and fields as one line.
#[derive(Default)]
struct Text(String);

impl Visit for Text {
    fn record_debug(&mut self, field: &Field, value: &dyn std::fmt::Debug) {
        let gap = if self.0.is_empty() { "" } else { " " };
        let _ = match field.name() {
            "message" => write!(self.0, "{gap}{value:?}"),
            name => write!(self.0, "{gap}{name}={value:?}"),
        };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy::log::tracing_subscriber::layer::SubscriberExt;
    use bevy::log::{info, trace};

    #[test]
    fn the_layer_keeps_messages_and_the_newest_are_read_by_level() {
        let messages = LogMessages::default();
        let subscriber = bevy::log::tracing_subscriber::registry().with(Capture(messages.clone()));
        bevy::log::tracing::subscriber::with_default(subscriber, || {
            info!("opened {}", "spot.obj");
            trace!(target: LAB_TARGET, "lab flip e7v0: h3v0 now v2v0 → v5v0");
            info!(faces = 5856, "loaded");
        });
        let all = messages.newest(Level::TRACE, 10, |_| true);
        let texts: Vec<&str> = all.iter().map(|m| m.text.as_str()).collect();
        assert_eq!(
            texts,
            [
                "loaded faces=5856",
                "lab flip e7v0: h3v0 now v2v0 → v5v0",
                "opened spot.obj"
            ]
        );
        assert_eq!(all[1].target, "lab");
        assert_eq!(messages.newest(Level::INFO, 10, |_| true).len(), 2);
        assert_eq!(
            messages
                .newest(Level::TRACE, 1, |m| m.target == "lab")
                .len(),
            1
        );
        for i in 0..LogMessages::CAPACITY {
            messages.push(LogMessage {
                level: Level::INFO,
                target: "t".into(),
                text: i.to_string(),
            });
        }
        let newest = messages.newest(Level::TRACE, LogMessages::CAPACITY + 1, |_| true);
        assert_eq!(newest.len(), LogMessages::CAPACITY);
        assert_eq!(newest[0].text, (LogMessages::CAPACITY - 1).to_string());
        assert!(log_filter().ends_with(",lab=trace"));
    }
}
