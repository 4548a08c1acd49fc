//! The audit streams its samples: the memory it holds at once does not grow
//! with the number of sampled points. (It used to keep every sample, so a
//! huge `--samples` panicked with "capacity overflow" or aborted.)
//!
//! A counting global allocator records the peak of the bytes allocated and
//! not yet freed during one audit. This file holds one test, so no other
//! thread allocates meanwhile.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use factor_audit::from_text::TextAudit;
use factor_audit::from_text::claims::TextDerivation;
use factor_audit::verdict::audit;
use factor_testing::samples::Sampler;

struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every call is forwarded to the system allocator unchanged; the
// counters only observe sizes.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let live = LIVE.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
        PEAK.fetch_max(live, Ordering::Relaxed);
        // SAFETY: the caller's contract is passed on.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        // SAFETY: the caller's contract is passed on.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// The peak of live bytes above the level at the start, while `f` runs.
fn peak_during(f: impl FnOnce()) -> usize {
    let start = LIVE.load(Ordering::Relaxed);
    PEAK.store(start, Ordering::Relaxed);
    f();
    PEAK.load(Ordering::Relaxed) - start
}

#[test]
fn memory_does_not_grow_with_the_samples() {
    let read = |path: &str| {
        std::fs::read_to_string(format!(
            "{}/../documents/{path}",
            env!("CARGO_MANIFEST_DIR")
        ))
        .unwrap()
    };
    let name = "001_85032ab900231dbd";
    let doc = TextAudit::load(
        name,
        &read(&format!("{name}.txt")),
        &read(&format!("{name}.symbols.toml")),
    )
    .unwrap();
    for claim in &doc.claims {
        let ctx = &doc.contexts[claim.context];
        let run = |samples| {
            drop(audit(
                |s: &mut Sampler| TextDerivation::new(claim, ctx, ctx.sample(s)),
                samples,
                TextAudit::seed(claim.index),
            ))
        };
        let few = peak_during(|| run(10));
        let many = peak_during(|| run(1000));
        // 100 times the samples: a kept sample of even a few bytes would add
        // kilobytes; the slack covers what one more worst sample may hold.
        assert!(
            many <= few + 4096,
            "{}: peak {many} bytes at 1000 samples, {few} at 10",
            claim.label.equation
        );
    }
}
