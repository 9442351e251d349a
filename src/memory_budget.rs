//! The memory budget: an operation whose result's size follows from its parameters
//! (subdivision levels, a remeshing length, a procedural shape's sizes, an extrusion of a large
//! selection) estimates the rows it will make before it starts, and is refused when their
//! memory exceeds the budget, with the estimate and the limit in the reason.
//!
//! Without it the process would find out by running out: Rust aborts on a failed allocation,
//! and an abort takes the editor's unsaved mesh with it. A refusal leaves the mesh as it was.
//!
//! The estimate is rows × [`BYTES_PER_ROW`], the memory
//! a bulk operation touches per vertex, halfedge, edge or face it makes (entities, components,
//! table rows and the operation's side tables, measured on Loop ×1 of the bunny). The budget is
//! [`Budget::Share`] of the memory the process can still get — the kernel's `MemAvailable`,
//! or less when an address-space limit (`ulimit -v`) leaves less room — by default 75 %, or a
//! fixed number of bytes. `pappus --max-memory`, the editor's panel and
//! `pappus.set_memory_budget` in Python change it for the whole process.

use std::sync::RwLock;

use thiserror::Error;

use crate::process_memory::BYTES_PER_ROW;

/// An estimate past the budget: the text gives the faces, the bytes, the limit and what to do
/// instead. Operations return it as `ops::Refusal::OverBudget`, readers as their parse error.
#[derive(Clone, Debug, PartialEq, Error)]
#[error("{0}")]
pub struct OverBudget(pub String);

/// How much memory operations may ask for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Budget {
    /// This share (0–1] of the memory available when the operation starts.
    Share(f64),
    /// This many bytes.
    Bytes(u64),
}

impl Default for Budget {
    /// 75 % of the available memory.
    fn default() -> Self {
        Budget::Share(0.75)
    }
}

/// The process's budget.
static BUDGET: RwLock<Budget> = RwLock::new(Budget::Share(0.75));

/// Sets the process's budget (every thread's operations).
pub fn set(budget: Budget) {
    *BUDGET.write().unwrap_or_else(|e| e.into_inner()) = budget;
}

/// The process's budget.
pub fn get() -> Budget {
    *BUDGET.read().unwrap_or_else(|e| e.into_inner())
}

impl Budget {
    /// Reads a budget: a share of the available memory (`75%`), or a size in bytes with an
    /// optional unit (`2G`, `1.5GiB`, `512M`, `800MB`, `1000000`; K, M, G, T are powers of
    /// 1024 with or without `iB`, and so are KB, MB, GB, TB).
    ///
    /// # Errors
    /// A message naming the text, for anything else, a share outside (0, 100] % or a size of 0.
    pub fn parse(text: &str) -> Result<Budget, String> {
        let bad = || {
            format!(
                "`{text}` is not a memory budget (expected a size such as 2G or 512M, or a share such as 50%)"
            )
        };
        let t = text.trim();
        if let Some(percent) = t.strip_suffix('%') {
            let p: f64 = percent.trim().parse().map_err(|_| bad())?;
            return if p > 0.0 && p <= 100.0 {
                Ok(Budget::Share(p / 100.0))
            } else {
                Err(bad())
            };
        }
        let split = t
            .find(|c: char| !(c.is_ascii_digit() || c == '.'))
            .unwrap_or(t.len());
        let (number, unit) = t.split_at(split);
        let number: f64 = number.parse().map_err(|_| bad())?;
        let scale: f64 = match unit.trim().to_ascii_uppercase().as_str() {
            "" | "B" => 1.0,
            "K" | "KB" | "KIB" => 1024.0,
            "M" | "MB" | "MIB" => 1024.0 * 1024.0,
            "G" | "GB" | "GIB" => 1024.0 * 1024.0 * 1024.0,
            "T" | "TB" | "TIB" => 1024.0 * 1024.0 * 1024.0 * 1024.0,
            _ => return Err(bad()),
        };
        let bytes = number * scale;
        if bytes >= 1.0 && bytes < u64::MAX as f64 {
            Ok(Budget::Bytes(bytes as u64))
        } else {
            Err(bad())
        }
    }

    /// The limit in bytes now, and how it was chosen ("75 % of available memory",
    /// "set with --max-memory"). A share of memory that cannot be measured (not Linux) is no
    /// limit (`u64::MAX`).
    pub fn limit(self) -> (u64, String) {
        match self {
            Budget::Bytes(bytes) => (bytes, "the limit set".into()),
            Budget::Share(share) => match available() {
                Some((available, limited)) => (
                    (available as f64 * share) as u64,
                    format!(
                        "{:.0} % of available memory{}",
                        share * 100.0,
                        if limited {
                            " under the address-space limit"
                        } else {
                            ""
                        }
                    ),
                ),
                None => (u64::MAX, "available memory unknown".into()),
            },
        }
    }
}

/// What an operation would make, for [`check`].
#[derive(Clone, Debug, PartialEq)]
pub struct Estimate {
    /// The operation as a person names it ("Loop ×5").
    pub what: String,
    /// The result's faces.
    pub faces: u64,
    /// The rows the operation makes (vertices, halfedges, edges and faces).
    pub rows: u64,
    /// What to do instead ("use fewer levels").
    pub instead: &'static str,
}

impl Estimate {
    /// The memory the rows take, about.
    pub fn bytes(&self) -> u64 {
        self.rows.saturating_mul(BYTES_PER_ROW as u64)
    }

    /// The rows of a mesh of `faces` triangles (about half as many vertices, three halfedges
    /// and one and a half edges a face: six rows a face).
    pub fn triangle_rows(faces: u64) -> u64 {
        faces.saturating_mul(6)
    }
}

/// Whether `estimate` fits the process's budget.
///
/// # Errors
/// [`OverBudget`], whose text gives the faces, the bytes, the limit and what to do instead:
/// "Loop ×5 would make 71 M faces, about 52 GB; the budget is 17 GB (75 % of available
/// memory): use fewer levels".
pub fn check(estimate: &Estimate) -> Result<(), OverBudget> {
    let (limit, why) = get().limit();
    let bytes = estimate.bytes();
    if bytes <= limit {
        return Ok(());
    }
    Err(OverBudget(format!(
        "{} would make {} faces, about {}; the budget is {} ({why}): {}",
        estimate.what,
        count(estimate.faces),
        size(bytes),
        size(limit),
        estimate.instead
    )))
}

/// A count as a person reads it: `71 M`, `350 k`, `1 200`.
pub fn count(n: u64) -> String {
    match n {
        0..10_000 => n.to_string(),
        10_000..10_000_000 => format!("{} k", n / 1000),
        10_000_000..10_000_000_000 => format!("{} M", n / 1_000_000),
        _ => format!("{} G", n / 1_000_000_000),
    }
}

/// Bytes as a person reads them, in powers of 1000 as `df -H` and file managers show: `52 GB`,
/// `640 MB`, `1.5 GB`.
pub fn size(bytes: u64) -> String {
    let b = bytes as f64;
    let (value, unit) = if b >= 1e12 {
        (b / 1e12, "TB")
    } else if b >= 1e9 {
        (b / 1e9, "GB")
    } else if b >= 1e6 {
        (b / 1e6, "MB")
    } else {
        (b / 1e3, "kB")
    };
    if value < 10.0 {
        format!("{value:.1} {unit}")
    } else {
        format!("{value:.0} {unit}")
    }
}

/// The memory the process can still get: the kernel's `MemAvailable`, or the room left under
/// an address-space limit if that is less. `None` where neither can be read.
pub fn available_memory() -> Option<u64> {
    available().map(|(bytes, _)| bytes)
}

/// [`available_memory`], and whether the address-space limit is what bounds it.
fn available() -> Option<(u64, bool)> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok();
    let available = meminfo
        .as_deref()
        .and_then(|m| kilobytes(m, "MemAvailable:"));
    match (available, address_space_room()) {
        (Some(a), Some(r)) => Some((a.min(r), r < a)),
        (Some(a), None) => Some((a, false)),
        (None, r) => r.map(|r| (r, true)),
    }
}

/// The value of a `NAME: N kB` line of a `/proc` file, in bytes.
fn kilobytes(text: &str, name: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with(name))?;
    let kb: u64 = line[name.len()..].split_whitespace().next()?.parse().ok()?;
    Some(kb.saturating_mul(1024))
}

/// The address space left under `ulimit -v` (the limit less what the process maps now, less
/// the heap's growth step, which an allocation reserves at once), or `None` without a limit.
fn address_space_room() -> Option<u64> {
    let limit = imp::address_space_limit()?;
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let mapped = kilobytes(&status, "VmSize:")?;
    let pad = crate::process_memory::GROWTH_PAD as u64;
    Some(limit.saturating_sub(mapped).saturating_sub(pad))
}

#[cfg(unix)]
mod imp {
    /// The soft address-space limit, or `None` when unlimited.
    #[allow(unsafe_code)]
    pub fn address_space_limit() -> Option<u64> {
        let mut limit = libc::rlimit {
            rlim_cur: 0,
            rlim_max: 0,
        };
        // SAFETY: `getrlimit` writes one `rlimit` through a valid pointer to a local.
        let ok = unsafe { libc::getrlimit(libc::RLIMIT_AS, &mut limit) } == 0;
        (ok && limit.rlim_cur != libc::RLIM_INFINITY).then_some(limit.rlim_cur)
    }
}

#[cfg(not(unix))]
mod imp {
    pub fn address_space_limit() -> Option<u64> {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn budgets_read_as_people_write_them() {
        let g = 1024u64 * 1024 * 1024;
        assert_eq!(Budget::parse("2G"), Ok(Budget::Bytes(2 * g)));
        assert_eq!(Budget::parse("1.5GiB"), Ok(Budget::Bytes(3 * g / 2)));
        assert_eq!(Budget::parse("512 MB"), Ok(Budget::Bytes(512 << 20)));
        assert_eq!(Budget::parse("1000"), Ok(Budget::Bytes(1000)));
        assert_eq!(Budget::parse("50%"), Ok(Budget::Share(0.5)));
        for bad in ["", "G", "0", "-1G", "2X", "0%", "150%", "lots"] {
            assert!(Budget::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn an_estimate_over_the_budget_is_refused_with_the_numbers() {
        let loop5 = Estimate {
            what: "Loop ×5".into(),
            faces: 71_000_000,
            rows: Estimate::triangle_rows(71_000_000),
            instead: "use fewer levels",
        };
        // 426 M rows × 114 bytes.
        assert_eq!(loop5.bytes(), 426_000_000 * BYTES_PER_ROW as u64);
        let refused = |budget| {
            set(budget);
            let r = check(&loop5);
            set(Budget::default());
            r
        };
        let Err(OverBudget(text)) = refused(Budget::Bytes(17_000_000_000)) else {
            panic!("not refused");
        };
        assert_eq!(
            text,
            "Loop ×5 would make 71 M faces, about 49 GB; the budget is 17 GB (the limit set): \
             use fewer levels"
        );
        assert!(refused(Budget::Bytes(60_000_000_000)).is_ok());
    }

    #[test]
    fn available_memory_is_measured_here() {
        // Other tests allocate and free meanwhile: the limit is half of a reading taken between
        // these two, so it lies within 5 % of half of theirs.
        let before = available_memory().expect("Linux has /proc/meminfo");
        let (limit, why) = Budget::Share(0.5).limit();
        let after = available_memory().expect("Linux has /proc/meminfo");
        assert!(before > 0 && after > 0 && limit > 0);
        let (low, high) = (before.min(after) as f64, before.max(after) as f64);
        assert!(
            (0.95 * low / 2.0..=1.05 * high / 2.0 + 1.0).contains(&(limit as f64)),
            "{limit} {before} {after}"
        );
        assert_eq!(why, "50 % of available memory");
    }

    #[test]
    fn counts_and_sizes_read_as_people_read_them() {
        assert_eq!(count(1200), "1200");
        assert_eq!(count(350_000), "350 k");
        assert_eq!(count(71_303_168), "71 M");
        assert_eq!(size(52_000_000_000), "52 GB");
        assert_eq!(size(1_500_000_000), "1.5 GB");
        assert_eq!(size(640_000_000), "640 MB");
    }
}
