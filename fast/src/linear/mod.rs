//! Sparse linear algebra of the fast solver: CSR matrices with a separate diagonal,
//! preconditioned conjugate gradients (pressure), BiCGStab (momentum), an aggregation algebraic
//! multigrid preconditioner, and thread-count-independent reductions.
//!
//! Determinism: every parallel loop writes disjoint outputs computed in a fixed order, and every
//! reduction sums fixed-size chunks ([`reduce::CHUNK`]; a gang's, [`reduce::GANG_CHUNK`]) whose
//! partial sums are added in chunk order, so a solve gives the same bits on 1 or N threads.
//! Conjugate gradients, the multigrid cycle and BiCGStab run as one gang of threads per solve
//! ([`gang`]), or on the calling thread alone when this machine has been running that solver's
//! gangs slower than one thread ([`pace`]); the other loops on rayon.

pub mod amg;
pub mod bicgstab;
pub mod csr;
pub mod gang;
pub mod pace;
pub mod pcg;
pub mod reduce;
pub mod smoother;

pub use csr::Csr;

/// Raw pointer for disjoint parallel writes (index i is written by exactly one task).
#[derive(Clone, Copy)]
pub struct Out<T>(pub *mut T);
unsafe impl<T> Send for Out<T> {}
unsafe impl<T> Sync for Out<T> {}
impl<T> Out<T> {
    pub fn of(v: &mut [T]) -> Self {
        Out(v.as_mut_ptr())
    }
    /// # Safety
    /// As [`Out::set`].
    #[inline]
    pub unsafe fn ptr(self, i: usize) -> *mut T {
        self.0.add(i)
    }
    /// # Safety
    /// `i` in bounds and written by one task only.
    #[inline]
    pub unsafe fn set(self, i: usize, value: T) {
        *self.0.add(i) = value;
    }
}

/// Loops of at most this many entries run on the calling thread alone (a hand-off to another
/// thread costs more than it saves).
const PARALLEL_MIN: usize = reduce::CHUNK;

/// Entries per task of the element-wise parallel loops. Smaller than the reduction chunk: with
/// 2048-entry tasks some loop lengths split badly between two threads (a red–black sweep of a
/// 192² grid, 9 tasks per colour, ran 1.14× faster on 2 threads than on 1, against 1.8× with
/// 512, when the sweeps still ran on rayon rather than in a [`gang`]), while 512 entries
/// still keep the per-task overhead small (2-thread lid 384² step −6 %, pressure solve −10 %;
/// 1 thread unchanged). Element-wise loops write disjoint outputs, so the task size does not
/// change any bits.
const PARALLEL_CHUNK: usize = 512;

/// f(i, &mut out[i]) for every i, in parallel over fixed chunks of [`PARALLEL_CHUNK`] entries
/// with a plain loop inside each chunk (no per-entry call through the parallel iterator, so the
/// loop body inlines and vectorises); short loops run on the calling thread without rayon.
#[inline]
pub fn par_update<T: Send>(out: &mut [T], f: impl Fn(usize, &mut T) + Sync + Send) {
    use rayon::prelude::*;
    let chunk = PARALLEL_CHUNK;
    if out.len() <= PARALLEL_MIN {
        for (i, y) in out.iter_mut().enumerate() {
            f(i, y);
        }
        return;
    }
    out.par_chunks_mut(chunk).enumerate().for_each(|(k, ys)| {
        let base = k * chunk;
        for (i, y) in ys.iter_mut().enumerate() {
            f(base + i, y);
        }
    });
}

/// f(i) for every i < n, chunked as [`par_update`] (for loops that write through [`Out`]).
#[inline]
pub fn par_range(n: usize, f: impl Fn(usize) + Sync + Send) {
    use rayon::prelude::*;
    let chunk = PARALLEL_CHUNK;
    if n <= PARALLEL_MIN {
        (0..n).for_each(f);
        return;
    }
    (0..n.div_ceil(chunk)).into_par_iter().for_each(|k| {
        for i in k * chunk..((k + 1) * chunk).min(n) {
            f(i);
        }
    });
}

/// Outcome of one iterative solve.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SolveStats {
    pub iterations: usize,
    /// Normalised residual (OpenFOAM's definition) before the first iteration.
    pub initial_residual: f64,
    /// Normalised residual at exit.
    pub final_residual: f64,
}

/// Iteration controls of one linear solve: stop when the normalised residual
/// Σ|b − Ax| / (Σ|Ax − Ax̄| + Σ|b − Ax̄| + 10⁻²⁰) falls below `tolerance` (x̄ the mean of the
/// initial guess, OpenFOAM's normalisation), or after `max_iterations`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerance {
    pub tolerance: f64,
    pub max_iterations: usize,
}

/// z = M⁻¹ r for a preconditioner M of matrix `a`, applied by every member of the gang that
/// runs the solve ([`gang`]).
pub trait Preconditioner: Sync {
    /// Adds the bytes its kernels stream to `bytes` (diagnostics).
    ///
    /// # Safety
    /// Every member of `crew` calls it with the same vectors, which no other gang uses (nor
    /// this preconditioner's work vectors: one solve at a time), and `z` is not `r`.
    unsafe fn apply(&self, crew: &gang::Crew, a: &Csr, r: &[gang::Slot<f64>], z: &[gang::Slot<f64>], bytes: &mut f64);

    /// Adds a solve's tally of `apply`'s bytes to the preconditioner's own.
    fn record_bytes(&mut self, _bytes: f64) {}
}

/// Diagonal (Jacobi) preconditioner.
pub struct Jacobi;

impl Preconditioner for Jacobi {
    unsafe fn apply(&self, crew: &gang::Crew, a: &Csr, r: &[gang::Slot<f64>], z: &[gang::Slot<f64>], _bytes: &mut f64) {
        // SAFETY: z[i] is written by its block's member only; r is not written
        crew.for_each(a.n, |i| unsafe { z[i].set(r[i].get() / a.diag[i]) });
    }
}
