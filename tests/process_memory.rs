//! The `pappus` program's allocator settings (`pappus::process_memory`), in a process of their
//! own as the program has them: set first thing in `main`, before any other thread exists.
//! (A test harness starts its threads first, so this test has no harness.)
//!
//! What must hold: memory warmed on another thread is what the next large allocation gets,
//! without page faults; freed memory is reused rather than faulted in again; warming on the
//! calling thread lasts as long as its caller asks; and a block allocated but not yet written
//! is faulted in by walking the heap, which goes no further than a little past the heap's last
//! block, however far it is allowed.

use pappus::process_memory::{
    FAULT_AHEAD_BYTES, fault_in_heap_while, faulting_in_ahead, keep_freed_memory, warm, warm_while,
    warming,
};
use std::cell::Cell;
use std::hint::black_box;

const PAGE: usize = 4096;
const BLOCK: usize = 64 << 20;

/// Page faults this thread has taken that needed no disk (`/proc/thread-self/stat`'s
/// `minflt`). The thread's own: the process's count also takes in a finished thread's faults,
/// at some moment after it was joined.
fn minor_faults() -> u64 {
    let stat = std::fs::read_to_string("/proc/thread-self/stat").expect("/proc/thread-self/stat");
    let after_name = &stat[stat.rfind(')').expect("a command name") + 2..];
    after_name
        .split_whitespace()
        .nth(7)
        .unwrap()
        .parse()
        .unwrap()
}

/// The process's resident memory in bytes (`/proc/self/statm`'s second field, in pages).
fn resident_bytes() -> usize {
    let statm = std::fs::read_to_string("/proc/self/statm").expect("/proc/self/statm");
    let pages: usize = statm.split_whitespace().nth(1).unwrap().parse().unwrap();
    pages * PAGE
}

/// A `busy` that holds for its first `asks` questions.
fn busy_for(asks: usize) -> impl Fn() -> bool {
    let asked = Cell::new(0);
    move || {
        asked.set(asked.get() + 1);
        asked.get() <= asks
    }
}

/// Page faults taken while writing to each page of a new block of `BLOCK` bytes.
fn faults_to_fill_a_block() -> u64 {
    let before = minor_faults();
    let mut block: Vec<u8> = Vec::with_capacity(BLOCK);
    for page in block.spare_capacity_mut().chunks_mut(PAGE) {
        page[0].write(1);
    }
    black_box(&block);
    minor_faults() - before
}

fn main() {
    if !cfg!(all(target_os = "linux", target_env = "gnu")) {
        assert!(!keep_freed_memory(), "only glibc on Linux is tuned");
        assert!(
            warm(BLOCK).is_none(),
            "nothing to warm into without kept memory"
        );
        println!("process_memory: not glibc on Linux; the allocator's defaults stay");
        return;
    }
    assert!(
        warm(BLOCK).is_none(),
        "warming before memory is kept would hand the block straight back"
    );
    assert_eq!(warm_while(BLOCK, || true), 0, "nor on this thread");
    assert_eq!(fault_in_heap_while(BLOCK, || true), 0, "nor the heap");
    assert!(keep_freed_memory(), "glibc accepts every setting");
    let pages = (BLOCK / PAGE) as u64;

    warm(BLOCK).expect("a warming thread").join().unwrap();
    assert!(!warming(), "the warming thread has finished");
    let after_warming = faults_to_fill_a_block();
    assert!(
        after_warming < pages / 20,
        "a warmed block faults in again: {after_warming} of {pages} pages"
    );

    // Freed memory stays. The allocator may take one more block of fresh pages before it
    // settles on the blocks it reuses; after that, filling a block again and again takes none.
    let settling = faults_to_fill_a_block();
    assert!(
        settling <= pages + pages / 20,
        "{settling} faults for {pages} pages"
    );
    let again: u64 = (0..6).map(|_| faults_to_fill_a_block()).sum();
    assert!(
        again < pages / 20,
        "freed blocks were handed back: {again} pages faulted in again over six fills"
    );
    assert_eq!(warm(0).map(|_| ()), None, "nothing to warm");

    // On the calling thread: for as long as `busy` says, asked every 256 KiB.
    assert_eq!(warm_while(BLOCK, busy_for(4)), 4 * (256 << 10));
    assert_eq!(warm_while(BLOCK, || true), BLOCK, "the whole block");
    assert_eq!(warm_while(0, || true), 0, "nothing to warm");

    // A block allocated and not yet written (larger than any freed so far, so fresh) is faulted
    // in by walking the heap, without allocating: then writing to it takes no faults.
    let fresh = 4 * BLOCK;
    let mut untouched: Vec<u8> = Vec::with_capacity(fresh);
    assert_eq!(fault_in_heap_while(fresh, || false), 0, "not busy: nothing");
    // Asked every MiB walked: busy for the block, the way past the heap's top, and a while of
    // waiting there for an allocation that does not come.
    let mib = 1 << 20;
    let walked = fault_in_heap_while(fresh, busy_for((fresh + FAULT_AHEAD_BYTES) / mib + 64));
    if walked == 0 {
        println!("process_memory: this kernel cannot populate pages (before Linux 5.14)");
    } else {
        assert!(
            walked >= fresh,
            "the block is in the heap walked ({walked} bytes)"
        );
        let before = minor_faults();
        for page in untouched.spare_capacity_mut().chunks_mut(PAGE) {
            page[0].write(1);
        }
        black_box(&untouched);
        let populated = minor_faults() - before;
        assert!(
            populated < 4 * pages / 20,
            "the populated block faulted in again: {populated} of {} pages",
            4 * pages
        );
    }
    // However far it may go, the walk stops a little past the heap's last block: every page
    // below it is resident by now, so what it adds is what it faulted in past the top.
    let before = resident_bytes();
    fault_in_heap_while(1 << 30, busy_for((1 << 30) / mib + 64));
    let added = resident_bytes().saturating_sub(before);
    assert!(
        added <= FAULT_AHEAD_BYTES + mib,
        "{added} bytes faulted in past the heap's top"
    );

    // Work beside a thread faulting in ahead of it: what it returns comes back unchanged, and a
    // panic in it stops that thread and is passed on, rather than leaving the thread waiting
    // for an allocation that never comes.
    let filled = faulting_in_ahead(BLOCK, || {
        vec![1u8; BLOCK].iter().map(|&b| b as usize).sum::<usize>()
    });
    assert_eq!(filled, BLOCK);
    let quiet = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let panicked = std::panic::catch_unwind(|| {
        faulting_in_ahead(BLOCK, || -> usize { panic!("the work failed") })
    });
    std::panic::set_hook(quiet);
    assert!(panicked.is_err(), "the work's panic is passed on");

    println!(
        "process_memory: {pages} pages; faults after warming {after_warming}, settling \
         {settling}, six fills after that {again}"
    );
}
