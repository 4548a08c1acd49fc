//! Where a solver iteration's time goes, measured from inside the factors.
//!
//! apex-solver evaluates every residual block once per pass, in parallel, in
//! a fixed order (by residual row): a linearization pass (residual and
//! Jacobian) before the linear solve, and a residual-only pass to evaluate
//! the step after it. Reading a clock in every factor call would cost as
//! much as a small kernel (about 40 ns a read here), so only two blocks read
//! it: the first in the solver's order marks the start of each pass at the
//! start of its call, the last the end of each pass at the end of its call.
//! Every block, this project's factors and apex's own alike, is wrapped in
//! [`Timed`], which forwards to it and reads the clock only for those two.
//! The problem builders of [`crate::problems`] insert blocks so that the
//! solver's order is the insertion order. On several threads the last block
//! ends its pass within one work chunk of the other threads.

use std::sync::Arc;

use apex_solver::core::variable::ManifoldVariable;
use apex_solver::factors::Factor;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// A factor's role in timing the passes: the first block of a pass marks
/// its start, the last its end (a lone block does both).
#[derive(Debug, Clone)]
pub struct Marks {
    /// The clock marked.
    pub clock: Arc<PhaseClock>,
    /// Whether this block is the first of each pass.
    pub first: bool,
    /// Whether this block is the last of each pass.
    pub last: bool,
}

impl Marks {
    /// The marks of block `index` of `count` on `clock`; `None` for the
    /// blocks in between, which read no clock.
    pub fn of_block(clock: &Arc<PhaseClock>, index: usize, count: usize) -> Option<Marks> {
        let (first, last) = (index == 0, index + 1 == count);
        (first || last).then(|| Marks {
            clock: Arc::clone(clock),
            first,
            last,
        })
    }
}

/// The latest pass of each kind, as nanoseconds since the clock's creation.
#[derive(Debug)]
pub struct PhaseClock {
    origin: Instant,
    /// `[linearization start, linearization end, evaluation start, evaluation end]`.
    marks: [AtomicU64; 4],
}

impl PhaseClock {
    /// A clock with no pass recorded.
    pub fn new() -> Arc<Self> {
        Arc::new(PhaseClock {
            origin: Instant::now(),
            marks: Default::default(),
        })
    }

    /// Records that a pass starts (`end` false) or ends (`end` true) now;
    /// `linearizing` tells the pass (with Jacobians, or residuals only).
    pub fn mark(&self, linearizing: bool, end: bool) {
        let index = usize::from(!linearizing) * 2 + usize::from(end);
        let now = u64::try_from(self.origin.elapsed().as_nanos()).unwrap_or(u64::MAX);
        self.marks[index].store(now, Ordering::Relaxed);
    }

    fn span(&self, start: usize) -> Duration {
        let from = self.marks[start].load(Ordering::Relaxed);
        let to = self.marks[start + 1].load(Ordering::Relaxed);
        Duration::from_nanos(to.saturating_sub(from))
    }

    /// The wall time of the latest linearization pass.
    pub fn linearization(&self) -> Duration {
        self.span(0)
    }

    /// The wall time of the latest residual-only pass.
    pub fn evaluation(&self) -> Duration {
        self.span(2)
    }
}

/// A residual block's factor, shared (the benchmarks keep a handle to call
/// it directly), and timing the passes if it is the first or the last.
pub struct Timed {
    /// The factor.
    pub factor: Arc<dyn Factor + Send + Sync>,
    /// Its marks, if it is the first or the last block.
    pub marks: Option<Marks>,
}

impl Factor for Timed {
    fn linearize(
        &self,
        params: &[&[f64]],
        residual: &mut [f64],
        jacobian: Option<faer::mat::MatMut<'_, f64>>,
    ) {
        let linearizing = jacobian.is_some();
        if let Some(marks) = self.marks.as_ref().filter(|m| m.first) {
            marks.clock.mark(linearizing, false);
        }
        self.factor.linearize(params, residual, jacobian);
        if let Some(marks) = self.marks.as_ref().filter(|m| m.last) {
            marks.clock.mark(linearizing, true);
        }
    }

    fn residual_dim(&self) -> usize {
        self.factor.residual_dim()
    }

    fn jacobian_shape(&self) -> (usize, usize) {
        self.factor.jacobian_shape()
    }

    fn whitens_internally(&self) -> bool {
        self.factor.whitens_internally()
    }

    fn validate_variables(&self, variables: &[&dyn ManifoldVariable]) -> Result<(), String> {
        self.factor.validate_variables(variables)
    }
}
