//! What the process's allocator does with freed memory: keep it for the next bulk operation
//! rather than hand it back to the kernel.
//!
//! A page a process writes for the first time costs a page fault, and the kernel zeroes it: on
//! the 2-core development machine about 0.3 ms per MB, whoever touches it and however
//! (`benches/spawn_floor.rs` measures it beside the spawns). Bulk operations allocate a lot:
//! Loop ×1 of the bunny touches about 181 MB of fresh pages, so in a fresh process about
//! 60 ms of its time is the kernel's, not Pappus's or Bevy's.
//!
//! The first time is unavoidable. Paying it *again* is not, and glibc's defaults do: a block
//! above its mmap threshold (128 KiB, rising to at most 32 MiB as blocks are freed) is a
//! mapping of its own, unmapped when freed, and a heap whose free top exceeds the trim
//! threshold is shrunk. Bevy's table columns and the operations' side tables are such blocks,
//! so an editor that subdivides, undoes and subdivides again faulted the same pages in twice.
//! [`keep_freed_memory`] makes glibc serve every block from its heaps and keep up to
//! [`KEPT_FREE_BYTES`] of freed memory for reuse.
//!
//! The first time can be paid ahead, on the other core: [`warm`] writes to a block of memory on
//! a thread of its own and frees it, so that the operation that follows finds its pages already
//! faulted in. `pappus process` does that while it reads and builds its input, when a step
//! subdivides (the steps that allocate most), sized from the input by [`BYTES_PER_ROW`], and
//! starts the steps once it is done. A thread that would otherwise wait on another does the
//! same with [`warm_while`]: the OBJ reader's first pass ends about 10 ms before `tobj` does on
//! the bunny, and faults in the pages of the mesh about to be built meanwhile.
//!
//! Memory an operation has already allocated, or will take next from the top of the heap, can
//! be faulted in from another thread without allocating anything: [`fault_in_heap_while`] asks
//! the kernel to populate the heap's pages (`MADV_POPULATE_WRITE`, which faults a page in as a
//! first write would, without writing). Subdivision's second thread does that once its tables
//! are computed, while the first thread is still spawning rows into fresh table columns, so the
//! two cores share the kernel's work instead of one waiting (two threads fault pages in 1.7
//! times as fast as one on the development machine); every other large table write (building a
//! mesh, an editor job's commit, the undo of a whole-mesh edit) starts a thread for just that
//! ([`faulting_in_ahead`]), and so does preparing a large mesh's tables before its rows are
//! spawned (the repair's working arrays and the tables: the 1.1 M-face scan's build took
//! 445 ms without it, 400 with it, medians of six alternating runs).
//! It follows the other thread's allocations, never more than [`FAULT_AHEAD_BYTES`] past the
//! heap's last block: a walk sized by a guess of what the rows take (it was [`BYTES_PER_ROW`] a
//! row ahead) overshot where a build reused freed blocks, and left 140–180 MiB of pages nobody
//! took resident on a million-face scan, a sixth of its peak.
//!
//! For the warmed block to be the memory the operation then gets, every thread allocates from
//! one arena; and the heap grows in large steps ([`GROWTH_PAD`]), because a heap extended a
//! little at a time under the warming thread's page faults makes the two threads wait on each
//! other.
//!
//! Not transparent huge pages: they make the first touch several times cheaper, but the kernel
//! may stall for hundreds of milliseconds finding or compacting 2 MiB pages, which an
//! interactive editor must not do (issue 26 measured both).
//!
//! Only the `pappus` program calls this, before anything is allocated in bulk. A library must
//! not change its host's allocator: the Python package leaves the interpreter's alone.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::thread::JoinHandle;

/// How much freed memory the process keeps mapped for reuse, at most (1 GiB: the rows of Loop
/// ×1 of a mesh of about 390 000 triangles); beyond it, freed memory goes back to the system.
pub const KEPT_FREE_BYTES: usize = 1 << 30;

/// How far the heap grows beyond each request (512 MiB of address space, not of memory: pages
/// are faulted in only when written).
pub const GROWTH_PAD: usize = 1 << 29;

/// The memory a bulk operation touches per row it makes (a vertex, halfedge, edge or face
/// entity, with its components, its place in Bevy's tables and the operation's side tables):
/// Loop ×1 of the bunny touched 181 MB of fresh pages for its 1.67 M rows.
pub const BYTES_PER_ROW: usize = 114;

/// How far past the heap's last allocated block [`fault_in_heap_while`] faults pages in (16 MiB):
/// enough that the block the other thread allocates next starts on pages already there, little
/// beside the hundreds of MB a bulk build allocates.
pub const FAULT_AHEAD_BYTES: usize = 16 << 20;

/// The least `limit` for which [`faulting_in_ahead`] starts a thread (8 MiB, about 2 000 pages:
/// where starting a thread costs microseconds and the pages milliseconds).
pub const FAULT_IN_MIN_BYTES: usize = 8 << 20;

/// The size of a page: the unit the kernel faults in.
const PAGE: usize = 4096;

/// Whether [`keep_freed_memory`] took effect.
static KEEPING: AtomicBool = AtomicBool::new(false);

/// The program break when [`keep_freed_memory`] took effect (0 before): every block the heap
/// serves after that lies above it, and [`fault_in_heap_while`] populates nothing below it.
static BREAK_WHEN_KEPT: AtomicUsize = AtomicUsize::new(0);

/// How many [`warm`] threads are running.
static WARMING: AtomicUsize = AtomicUsize::new(0);

/// Whether [`keep_freed_memory`] took effect: the `pappus` program, not the library or the
/// Python package. Without it, warming and faulting in ahead do nothing, so callers need not
/// start a thread for them.
pub fn keeps_freed_memory() -> bool {
    KEEPING.load(Ordering::Relaxed)
}

/// Whether a [`warm`] thread is running: work that would spread over the cores (the OBJ
/// reader's second thread) runs on one instead, leaving the other to the warming.
pub fn warming() -> bool {
    WARMING.load(Ordering::Relaxed) > 0
}

/// Tells the allocator to keep freed memory for reuse and to serve every thread from one arena
/// (see the module doc). Returns whether it took effect: `false` on systems other than glibc on
/// Linux, where the allocator's own defaults stay.
pub fn keep_freed_memory() -> bool {
    let kept = imp::keep_freed_memory();
    if kept {
        BREAK_WHEN_KEPT.store(imp::heap_end(), Ordering::Relaxed);
    }
    KEEPING.store(kept, Ordering::Relaxed);
    kept
}

/// Writes to `bytes` of fresh memory (one byte a page) on a thread of its own, then frees it,
/// so that what is allocated next finds those pages faulted in. Returns the thread, or `None`
/// when memory is not kept ([`keep_freed_memory`] was not called or did not take effect: the
/// block would go straight back to the system), `bytes` is 0, or no thread could be started.
/// At most [`KEPT_FREE_BYTES`] are warmed.
pub fn warm(bytes: usize) -> Option<JoinHandle<()>> {
    if !keeps_freed_memory() || bytes == 0 {
        return None;
    }
    WARMING.fetch_add(1, Ordering::Relaxed);
    let spawned = std::thread::Builder::new()
        .name("warm memory".into())
        .spawn(move || {
            warm_while(bytes, || true);
            WARMING.fetch_sub(1, Ordering::Relaxed);
        });
    if spawned.is_err() {
        WARMING.fetch_sub(1, Ordering::Relaxed);
    }
    spawned.ok()
}

/// Writes to fresh memory (one byte a page) on the calling thread while `busy()` holds, up to
/// `bytes` (and at most [`KEPT_FREE_BYTES`]), then frees it: for a thread that would otherwise
/// wait on another (the OBJ reader, for `tobj`) to fault in the pages of what it builds next.
/// `busy` is asked every 256 KiB, so it stops within about 0.1 ms of `busy()` turning false.
/// Returns the bytes warmed: 0 when memory is not kept (see [`warm`]).
pub fn warm_while(bytes: usize, busy: impl Fn() -> bool) -> usize {
    const ASK_EVERY: usize = 64 * PAGE;
    if !keeps_freed_memory() {
        return 0;
    }
    let mut block: Vec<u8> = Vec::with_capacity(bytes.min(KEPT_FREE_BYTES));
    let mut warmed = 0;
    for chunk in block.spare_capacity_mut().chunks_mut(ASK_EVERY) {
        if !busy() {
            break;
        }
        for page in chunk.chunks_mut(PAGE) {
            page[0].write(0);
        }
        warmed += chunk.len();
    }
    std::hint::black_box(&block);
    warmed
}

/// Faults in the heap's pages from the calling thread while `busy()` holds, from `limit` bytes
/// below the free top of the heap to `limit` bytes into it: the blocks allocated last but not
/// yet written (the table columns another thread is filling), then what the next allocations
/// take. It never runs more than [`FAULT_AHEAD_BYTES`] past where the heap's blocks reach at the
/// moment: it waits for the other thread's allocations rather than guess how far they will go,
/// so that pages nobody takes are not left resident. For a thread that has finished its share of
/// a bulk operation while another still writes fresh memory. `busy` is asked every MiB and
/// while waiting. Nothing is allocated or written: the kernel populates the pages as a first
/// write would (`MADV_POPULATE_WRITE`, which faults a page in without writing), so what they
/// hold is unchanged. Returns the bytes walked (pages already present included); 0 when memory
/// is not kept (see [`keep_freed_memory`]) or the kernel cannot populate (Linux before 5.14).
pub fn fault_in_heap_while(limit: usize, busy: impl Fn() -> bool) -> usize {
    const STEP: usize = 1 << 20;
    let floor = BREAK_WHEN_KEPT.load(Ordering::Relaxed);
    if !keeps_freed_memory() || floor == 0 {
        return 0;
    }
    let top = imp::heap_top_start();
    let stop = top.saturating_add(limit);
    let mut at = top.saturating_sub(limit).max(floor).next_multiple_of(PAGE);
    let mut walked = 0;
    while at < stop && busy() {
        let reach = imp::heap_top_start()
            .saturating_add(FAULT_AHEAD_BYTES)
            .min(imp::heap_end())
            .min(stop);
        let len = STEP.min(reach.saturating_sub(at)) / PAGE * PAGE;
        if len == 0 {
            // As far ahead as it may go: wait for the next allocation.
            std::thread::sleep(std::time::Duration::from_micros(50));
            continue;
        }
        if !imp::populate(at, len) {
            break;
        }
        at += len;
        walked += len;
    }
    walked
}

/// Runs `work` on the calling thread while a second thread faults the heap's pages in ahead of
/// it ([`fault_in_heap_while`] with `limit`, until `work` returns), so that the kernel's share of
/// a bulk operation that writes fresh memory (building a mesh's tables, spawning its rows) is
/// spread over two cores. Returns what `work` returned, unchanged: faulting a page in changes no
/// byte of it. Runs `work` alone where memory is not kept ([`keeps_freed_memory`]: the library
/// and the Python package), where no thread can be started, or when `limit` is under
/// [`FAULT_IN_MIN_BYTES`]. A panic in `work` ends the second thread and is passed on.
pub fn faulting_in_ahead<T>(limit: usize, work: impl FnOnce() -> T) -> T {
    if !keeps_freed_memory() || limit < FAULT_IN_MIN_BYTES {
        return work();
    }
    let done = AtomicBool::new(false);
    std::thread::scope(|scope| {
        // Where no thread can be started, the work runs alone, as where no memory is kept.
        let _faulting = std::thread::Builder::new()
            .name("fault in ahead".into())
            .spawn_scoped(scope, || {
                fault_in_heap_while(limit, || !done.load(Ordering::Relaxed))
            });
        let _done = SetOnDrop(&done);
        work()
    })
}

/// Sets its flag when dropped: when the work it stands beside returns or unwinds. What tells a
/// thread faulting pages in ahead of that work ([`fault_in_heap_while`]'s `busy`) to stop, so
/// that a panic in the work is passed on instead of leaving the thread waiting for allocations
/// that never come.
pub(crate) struct SetOnDrop<'a>(pub(crate) &'a AtomicBool);

impl Drop for SetOnDrop<'_> {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Relaxed);
    }
}

#[cfg(all(target_os = "linux", target_env = "gnu"))]
mod imp {
    use super::{GROWTH_PAD, KEPT_FREE_BYTES};
    use std::ffi::c_int;

    #[allow(unsafe_code)]
    pub fn keep_freed_memory() -> bool {
        let trim = c_int::try_from(KEPT_FREE_BYTES).unwrap_or(c_int::MAX);
        let pad = c_int::try_from(GROWTH_PAD).unwrap_or(c_int::MAX);
        // SAFETY: `mallopt` only sets glibc malloc's tuning parameters; it takes plain integers,
        // keeps no pointers, and is documented as callable at any time, by any thread (it takes
        // the arenas' locks). Blocks already allocated are unaffected.
        unsafe {
            // No block gets a mapping of its own: all come from the heaps, where freed memory
            // is reused...
            let no_own_mappings = libc::mallopt(libc::M_MMAP_MAX, 0) == 1;
            // ...and the heaps keep up to KEPT_FREE_BYTES free before shrinking.
            let keep = libc::mallopt(libc::M_TRIM_THRESHOLD, trim) == 1;
            // One arena for every thread, so memory one thread warmed (`warm`) is what the
            // others get...
            let one_arena = libc::mallopt(libc::M_ARENA_MAX, 1) == 1;
            // ...and a heap that grows in large steps, not under a warming thread's faults.
            let pad = libc::mallopt(libc::M_TOP_PAD, pad) == 1;
            no_own_mappings && keep && one_arena && pad
        }
    }

    /// The end of the heap (the program break), as the kernel has it.
    #[allow(unsafe_code)]
    pub fn heap_end() -> usize {
        // SAFETY: `brk(0)` asks the kernel for the current break and changes nothing (no break
        // is at address 0). The raw system call, not glibc's `sbrk(0)`, which reads a variable
        // that another thread's `malloc` may be writing.
        unsafe { libc::syscall(libc::SYS_brk, 0) as usize }
    }

    /// Where the free top of the heap begins: what the next allocation that fits no freed
    /// block takes.
    #[allow(unsafe_code)]
    pub fn heap_top_start() -> usize {
        // SAFETY: `mallinfo` takes the arenas' locks and returns statistics by value;
        // `keepcost` is the size of the main arena's top chunk, which ends at the break. (Not
        // `mallinfo2`, which glibc has only from 2.33; `keepcost` is an `int` here, read as
        // unsigned: the top chunk stays well under 4 GiB, as memory kept is 1 GiB at most.)
        let top = unsafe { libc::mallinfo() }.keepcost as u32 as usize;
        heap_end().saturating_sub(top)
    }

    /// Populates `len` bytes at `at` (page-aligned, inside the heap) as a first write would,
    /// without writing. Whether the kernel did (it refuses before Linux 5.14, or a range no
    /// longer mapped).
    #[allow(unsafe_code)]
    pub fn populate(at: usize, len: usize) -> bool {
        const MADV_POPULATE_WRITE: std::ffi::c_int = 23;
        // SAFETY: `MADV_POPULATE_WRITE` faults pages in and changes no byte of memory: an
        // absent page becomes the zero page a first write would have found, a present one is
        // left as it is. So no value of any allocated block changes, whichever thread owns it
        // and whatever it is doing. A range the heap no longer maps makes the call fail
        // (ENOMEM), and the caller stops.
        unsafe { libc::madvise(at as *mut libc::c_void, len, MADV_POPULATE_WRITE) == 0 }
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
mod imp {
    pub fn keep_freed_memory() -> bool {
        false
    }

    pub fn heap_end() -> usize {
        0
    }

    pub fn heap_top_start() -> usize {
        0
    }

    pub fn populate(_at: usize, _len: usize) -> bool {
        false
    }
}
