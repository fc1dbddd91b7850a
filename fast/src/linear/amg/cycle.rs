//! One cycle of the hierarchy (parent module doc): the smoothing sweeps, the restriction and
//! prolongation, the K-cycle's coarse Krylov steps and the coarsest solve, run by the members of
//! a gang; the coarse corrections of small levels by one member alone ([`SOLO_ROWS`]).

use super::super::csr::{Csr, Real};
use super::super::gang::{self, Crew, PartialSum, Slot};
use super::super::smoother::{sweep, sweep_from_zero};
use super::{Dense, LevelWork, Smoother, Transfer, DENSE_LIMIT, KCYCLE_MIN_RATIO, KCYCLE_MIN_ROWS, KCYCLE_SKIP, SOLO_ROWS};

/// Bytes of one entry of `T`.
fn size<T>() -> f64 {
    std::mem::size_of::<T>() as f64
}

/// Bytes of a matrix pass: row starts, columns, values and diagonal.
fn matrix_bytes<T: Real>(a: &Csr<T>) -> f64 {
    (4.0 + size::<T>()) * a.col.len() as f64 + 4.0 * (a.n + 1) as f64 + size::<T>() * a.n as f64
}

/// A multicolour sweep on vectors of `V`: the matrix without its diagonal, the colour order,
/// b, 1/diag and x read and written.
fn sweep_bytes<T: Real, V: Real>(a: &Csr<T>) -> f64 {
    matrix_bytes(a) + (4.0 + 3.0 * size::<V>()) * a.n as f64
}

/// Read-only parts of the hierarchy.
pub(super) struct Levels<'a> {
    pub(super) transfers: &'a [Transfer],
    pub(super) coarse: &'a [Csr<f32>],
    pub(super) smoothers: &'a [Smoother],
    pub(super) dense: Option<&'a Dense>,
    pub(super) coarsest: &'a Smoother,
    pub(super) solo_partials: &'a [PartialSum],
}

/// Exact (dense) or approximate (two symmetric sweeps, when coarsening stalled) coarsest solve.
///
/// # Safety (this function, [`cycle`] and [`k_cycle_correction`])
/// Every member of `crew` calls it with the same vectors and work sets, which no other gang
/// uses, `x` not being `b`. (The levels' colourings are built from their own matrices in
/// [`Amg::setup`], as the sweeps require.)
unsafe fn coarsest<V: Real>(crew: &Crew, a: &Csr<f32>, b: &[Slot<V>], x: &[Slot<V>], levels: &Levels, bytes: &mut f64) {
    match levels.dense {
        Some(d) => {
            *bytes += 8.0 * (d.n * d.n) as f64 + 2.0 * size::<V>() * d.n as f64;
            crew.alone(|| {
                let mut bd = [0.0; DENSE_LIMIT];
                let mut xd = [0.0; DENSE_LIMIT];
                // SAFETY: b was written before the last barrier; x is written by this member
                // alone, read by the others after the barrier of `alone`
                for (bd, b) in bd.iter_mut().zip(b) {
                    *bd = unsafe { b.get() }.get();
                }
                d.solve(&bd[..d.n], &mut xd[..d.n]);
                for (x, xd) in x.iter().zip(&xd) {
                    unsafe { x.set(V::put(*xd)) };
                }
            });
        }
        None => {
            let s = levels.coarsest;
            *bytes += 4.0 * sweep_bytes::<f32, V>(a);
            // SAFETY: the caller's promise
            unsafe {
                sweep_from_zero(crew, a, &s.inv_diag, &s.colouring, b, x);
                for forward in [false, true, false] {
                    sweep(crew, a, &s.inv_diag, &s.colouring, b, x, forward);
                }
            }
        }
    }
}

/// x = B b, one cycle from x = 0 on level `k` (matrix `a`), by the members of a gang. Level 0
/// works on the f64 vectors of CG (`V` = f64) with the f32 matrix copy; the coarse levels on f32
/// vectors. Every kernel computes in f64.
///
/// # Safety
/// As [`coarsest`].
#[allow(clippy::too_many_arguments)]
pub(super) unsafe fn cycle<V: Real>(crew: &Crew, a: &Csr<f32>, b: &[Slot<V>], x: &[Slot<V>], levels: &Levels, k: usize, work: &[LevelWork], bytes: &mut f64) {
    // SAFETY (the calls below): the caller's promise, passed on with this level's own work
    // set (bc, xc distinct) to the next level
    if k == levels.transfers.len() {
        unsafe { coarsest(crew, a, b, x, levels, bytes) };
        return;
    }
    let t = &levels.transfers[k];
    let s = &levels.smoothers[k];
    let ac = &levels.coarse[k];
    *bytes += cycle_bytes::<V>(a, t, s, ac.n);
    let (w, rest) = work.split_first().expect("one work set per transfer");
    unsafe { sweep_from_zero(crew, a, &s.inv_diag, &s.colouring, b, x) };
    // restricted residual bc = Pᵀ(b − A x), fused (no fine residual vector)
    crew.for_each(w.bc.len(), |c| {
        let mut sum = 0.0;
        for &i in &t.residual_members[t.residual_start[c] as usize..t.residual_start[c + 1] as usize] {
            let i = i as usize;
            // SAFETY: b and x are not written in this loop; bc[c] by its block's member only
            sum += unsafe { b[i].get().get() - a.diag[i].get() * x[i].get().get() - a.row_off_diagonal_shared(i, x) };
        }
        unsafe { w.bc[c].set(sum as f32) };
    });
    let correction = |crew: &Crew, bytes: &mut f64| {
        if k + 1 == levels.transfers.len() {
            unsafe { coarsest(crew, ac, &w.bc, &w.xc, levels, bytes) };
        } else if ac.n * KCYCLE_MIN_RATIO <= a.n && ac.n >= KCYCLE_MIN_ROWS {
            unsafe { k_cycle_correction(crew, ac, w, levels, k + 1, rest, bytes) };
        } else {
            // poor coarsening (weakly coupled rows near the bottom of the hierarchy): one visit,
            // or the K-cycle's two visits per level would multiply without the work shrinking
            unsafe { cycle(crew, ac, &w.bc, &w.xc, levels, k + 1, rest, bytes) };
        }
    };
    if crew.size() > 1 && ac.n < SOLO_ROWS {
        // one member computes what the gang would (a gang of one has any gang's bits), the
        // others meet it at the barrier of `alone`, after which they read xc
        crew.alone(|| gang::solo(levels.solo_partials, |solo| correction(solo, bytes)));
    } else {
        correction(crew, bytes);
    }
    // prolongation; the backward sweep starts with the last colour and overwrites those rows
    // from their (corrected) neighbours alone, so they are not corrected here
    let xc = &w.xc;
    let corrected = &s.colouring.order[..s.colouring.start[s.colouring.colours().saturating_sub(1)] as usize];
    crew.for_each(corrected.len(), |m| {
        let i = corrected[m] as usize;
        // SAFETY: every row appears once in the colour order, so x[i] has one writer; xc is
        // not written in this loop
        unsafe { x[i].set(V::put(x[i].get().get() + xc[t.agg[i] as usize].get() as f64)) };
    });
    unsafe { sweep(crew, a, &s.inv_diag, &s.colouring, b, x, false) };
}

/// Bytes one visit of [`cycle`] streams on a level of `a.n` rows above one of `nc`: the
/// zero-start sweep (the first colour without the matrix), the restriction of the residuals
/// that are not zero, the prolongation to the rows the backward sweep does not overwrite, and
/// the backward sweep.
fn cycle_bytes<V: Real>(a: &Csr<f32>, t: &Transfer, s: &Smoother, nc: usize) -> f64 {
    let n = a.n as f64;
    let first = s.colouring.start.get(1).copied().unwrap_or(0) as f64;
    let last = s.colouring.start.len().checked_sub(2).map_or(0, |k| s.colouring.start[k]) as f64;
    let row_share = |rows: f64| if n > 0.0 { rows / n } else { 0.0 };
    let zero_start = sweep_bytes::<f32, V>(a) * row_share(n - first) + (4.0 + 2.0 * size::<V>() + 4.0) * first;
    let restricted = t.residual_members.len() as f64;
    let restriction = matrix_bytes(a) * row_share(restricted) + (4.0 + 2.0 * size::<V>()) * restricted + 12.0 * nc as f64;
    let prolongation = (12.0 + 2.0 * size::<V>()) * last;
    zero_start + restriction + prolongation + sweep_bytes::<f32, V>(a)
}

/// Coarse correction xc ≈ Aᶜ⁻¹ bc on level `k` by at most two flexible-CG steps preconditioned
/// with the next cycle (Notay & Vassilevski 2008, Algorithm 3.1 with t = [`KCYCLE_SKIP`]).
///
/// # Safety
/// As [`coarsest`].
//
// SAFETY (every unsafe block below): a loop writes only its own entries (its block's, or its
// chunk's in a sum) of a vector it does not read elsewhere; vectors written by one loop are
// read by later loops, after the barrier that ends it. The cycles and products called get
// this level's distinct work vectors, and every member calls them in step (the branches follow
// sums all members compute alike).
unsafe fn k_cycle_correction(crew: &Crew, ac: &Csr<f32>, w: &LevelWork, levels: &Levels, k: usize, rest: &[LevelWork], bytes: &mut f64) {
    let n = ac.n;
    let LevelWork { bc, xc, v1, v2, w1, w2, rt } = w;
    let at = |v: &[Slot<f32>], i: usize| unsafe { v[i].get() } as f64;
    unsafe { cycle(crew, ac, bc, v1, levels, k, rest, bytes) };
    let nf = n as f64;
    // product with two sums, two sums, residual update (f32 vectors)
    *bytes += matrix_bytes(ac) + 12.0 * nf + 8.0 * nf + 12.0 * nf;
    let [rho1, alpha1] = unsafe { ac.multiply_sum2_shared(crew, v1, w1, |i, w| [at(v1, i) * w, at(v1, i) * at(bc, i)]) };
    if rho1 <= 0.0 || !rho1.is_finite() {
        crew.for_each(n, |i| unsafe { xc[i].set(0.0) });
        return;
    }
    let a1 = alpha1 / rho1;
    crew.for_each(n, |i| unsafe { rt[i].set((at(bc, i) - a1 * at(w1, i)) as f32) });
    let [rt2, bc2] = crew.sum2(n, |i| [at(rt, i) * at(rt, i), at(bc, i) * at(bc, i)]);
    if rt2 <= KCYCLE_SKIP * KCYCLE_SKIP * bc2 {
        *bytes += 8.0 * nf;
        crew.for_each(n, |i| unsafe { xc[i].set((a1 * at(v1, i)) as f32) });
        return;
    }
    unsafe { cycle(crew, ac, rt, v2, levels, k, rest, bytes) };
    // product with two sums, a sum, combination
    *bytes += matrix_bytes(ac) + 12.0 * nf + 8.0 * nf + 12.0 * nf;
    let [gamma, beta] = unsafe { ac.multiply_sum2_shared(crew, v2, w2, |i, w| [at(v2, i) * at(w1, i), at(v2, i) * w]) };
    let alpha2 = crew.sum(n, |i| at(v2, i) * at(rt, i));
    let rho2 = beta - gamma * gamma / rho1;
    if rho2 <= 0.0 || !rho2.is_finite() {
        crew.for_each(n, |i| unsafe { xc[i].set((a1 * at(v1, i)) as f32) });
        return;
    }
    let (c1, c2) = (a1 - gamma * alpha2 / (rho1 * rho2), alpha2 / rho2);
    crew.for_each(n, |i| unsafe { xc[i].set((c1 * at(v1, i) + c2 * at(v2, i)) as f32) });
}
