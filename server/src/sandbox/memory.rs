//! The engine's memory limit, kept by its allocator: QuickJS says "out of memory" with an
//! error the student's code can catch and imitate (`throw new InternalError('out of
//! memory')`, or `null`, what it throws when even that error cannot be made), so whether
//! a phase ran out of memory is decided here, by an allocation refused, not by what was
//! thrown.

use super::cpu::CpuClock;
use super::watchdog::Pulse;
use rquickjs::allocator::{Allocator, RustAllocator};
use std::cell::RefCell;
use std::rc::Rc;
use std::sync::Arc;

/// Blocks from this size up are shown to the watchdog as a look at the clock.
///
/// One bytecode step can take long inside the allocator: a typed array of megabytes is a
/// block glibc zeroes (once it has raised its mmap threshold, it takes such blocks from
/// the heap), and QuickJS looks at its clock only every 10,000 steps or so. A loop that
/// makes and drops such arrays spends seconds of CPU between two looks, making progress
/// all along, so the allocator tells the watchdog, as the engine does, that its thread is
/// not stalled in one call.
const LOOKS_FROM: usize = 64 << 10;

/// Rust's allocator with a limit on the bytes in use, which remembers being refused and
/// what the engine was running then (as its `Pulse` says).
pub struct Metered {
    limit: usize,
    used: usize,
    /// The engine's thread's clock, for the pulse.
    clock: CpuClock,
    pulse: Arc<Pulse>,
    refused: Rc<RefCell<Option<String>>>,
}

impl Metered {
    /// An allocator of at most `limit` bytes that, when it first refuses one, puts in
    /// `refused` what `pulse` says the engine runs (the label is made with Rust's own
    /// allocator, not this one). Made on the engine's thread, which it then serves alone.
    pub fn new(limit: usize, pulse: Arc<Pulse>, refused: Rc<RefCell<Option<String>>>) -> Metered {
        Metered {
            limit,
            used: 0,
            clock: CpuClock::of_this_thread(),
            pulse,
            refused,
        }
    }

    /// Whether `size` more bytes, in place of `freed`, stay within the limit; if not, the
    /// first refusal is remembered.
    fn fits(&self, size: usize, freed: usize) -> bool {
        let fits = (self.used - freed)
            .checked_add(size)
            .is_some_and(|total| total <= self.limit);
        if !fits {
            let mut refused = self.refused.borrow_mut();
            if refused.is_none() {
                *refused = Some(self.pulse.label());
            }
        }
        fits
    }

    /// After a block of `size` was made: a large one is a look at the clock (`LOOKS_FROM`).
    fn looked_after(&self, size: usize) {
        if size >= LOOKS_FROM
            && let Some(now) = self.clock.read()
        {
            self.pulse.looked(now);
        }
    }

    /// Counts a new block (a null pointer is none).
    fn counted(&mut self, ptr: *mut u8) -> *mut u8 {
        if !ptr.is_null() {
            // SAFETY: a block just made by RustAllocator.
            self.used += unsafe { RustAllocator::usable_size(ptr) };
        }
        ptr
    }
}

// SAFETY: every block is made, resized and freed by RustAllocator, which meets the
// trait's requirements; this only refuses some requests (with a null pointer, which the
// trait allows) and counts sizes.
unsafe impl Allocator for Metered {
    fn alloc(&mut self, size: usize) -> *mut u8 {
        if !self.fits(size, 0) {
            return std::ptr::null_mut();
        }
        let ptr = RustAllocator.alloc(size);
        self.looked_after(size);
        self.counted(ptr)
    }

    fn calloc(&mut self, count: usize, size: usize) -> *mut u8 {
        match count.checked_mul(size) {
            Some(total) if self.fits(total, 0) => {
                let ptr = RustAllocator.calloc(count, size);
                self.looked_after(total);
                self.counted(ptr)
            }
            _ => std::ptr::null_mut(),
        }
    }

    unsafe fn dealloc(&mut self, ptr: *mut u8) {
        // SAFETY: the caller hands back a block of this allocator.
        unsafe {
            self.used -= RustAllocator::usable_size(ptr);
            RustAllocator.dealloc(ptr);
        }
    }

    unsafe fn realloc(&mut self, ptr: *mut u8, new_size: usize) -> *mut u8 {
        // QuickJS resizes no null pointer and frees rather than resize to nothing (its
        // js_realloc_rt), but the C interface allows both.
        if ptr.is_null() {
            return self.alloc(new_size);
        }
        // SAFETY: the caller hands over a block of this allocator.
        unsafe {
            if new_size == 0 {
                self.dealloc(ptr);
                return std::ptr::null_mut();
            }
            let old = RustAllocator::usable_size(ptr);
            if !self.fits(new_size, old) {
                return std::ptr::null_mut();
            }
            let moved = RustAllocator.realloc(ptr, new_size);
            self.looked_after(new_size);
            if !moved.is_null() {
                self.used = self.used - old + RustAllocator::usable_size(moved);
            }
            moved
        }
    }

    unsafe fn usable_size(ptr: *mut u8) -> usize {
        // SAFETY: the caller hands over a block of this allocator.
        unsafe { RustAllocator::usable_size(ptr) }
    }
}
