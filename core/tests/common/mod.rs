//! Shared by the integration tests that prove "no heap allocation per sample".
//!
//! A counting global allocator wraps `System`. Counting is switched on per thread
//! (a thread-local flag), so tests running in parallel threads do not disturb it.
//! Including this module (`mod common;`) installs the allocator in that test binary.

#![allow(dead_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};

struct CountingAlloc;

thread_local! {
    /// Whether allocations of this thread are counted.
    static COUNTING: Cell<bool> = const { Cell::new(false) };
    /// Allocations counted on this thread.
    static COUNT: Cell<usize> = const { Cell::new(0) };
}

/// Allocations seen by the allocator on any thread (sanity only).
static TOTAL: AtomicUsize = AtomicUsize::new(0);

impl CountingAlloc {
    fn note(&self) {
        TOTAL.fetch_add(1, Ordering::Relaxed);
        // `try_with`: the thread-locals may already be gone while a thread is torn down.
        if COUNTING.try_with(Cell::get).unwrap_or(false) {
            let _ = COUNT.try_with(|c| c.set(c.get() + 1));
        }
    }
}

// SAFETY: every call is forwarded unchanged to the system allocator.
#[allow(unsafe_code)] // a GlobalAlloc can only be implemented unsafely
unsafe impl GlobalAlloc for CountingAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        self.note();
        System.alloc(layout)
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        self.note();
        System.alloc_zeroed(layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        self.note();
        System.realloc(ptr, layout, new_size)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
}

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

/// Heap allocations (alloc, alloc_zeroed, realloc) made by `f` on the current thread.
pub fn allocations_in<R>(f: impl FnOnce() -> R) -> (usize, R) {
    COUNT.with(|c| c.set(0));
    COUNTING.with(|c| c.set(true));
    let r = f();
    COUNTING.with(|c| c.set(false));
    (COUNT.with(Cell::get), r)
}

/// Allocations seen on any thread so far.
pub fn total_allocations() -> usize {
    TOTAL.load(Ordering::Relaxed)
}
