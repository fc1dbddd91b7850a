//! Sums whose bits do not depend on the number of threads: the index range is cut into chunks
//! of [`CHUNK`] entries (a gang's sums: [`GANG_CHUNK`]; constants, not functions of the thread
//! count), each chunk is summed in index order, and the chunk sums are added in chunk order.

use rayon::prelude::*;

/// Entries per reduction chunk and minimum work per parallel task.
pub const CHUNK: usize = 2048;

/// Reusable buffer of chunk partial sums (no allocation once it is large enough).
#[derive(Clone, Debug, Default)]
pub struct Reducer {
    partial: Vec<[f64; 2]>,
}

/// Entries per chunk of a gang's sums ([`super::gang::Crew::sum2`]). Smaller than [`CHUNK`]: a
/// gang's member sums whole chunks, so a sum over 9 840 rows (P3 fine's pressure) in chunks of
/// 2 048 went 3 : 2 between two members, and one over its first coarse level's 2 460 rows
/// 2 048 : 412; in chunks of 256 the members' shares differ by at most one chunk. (P3 fine's
/// pressure solve on two threads: about 10 % less time, measured with `pressure_solve` on a
/// 100² grid.)
pub const GANG_CHUNK: usize = 256;

/// The sums of chunk k (of `chunk` entries) of a sum over `0..n`: its entries added in index
/// order.
#[inline(always)]
pub fn chunk_sum(k: usize, chunk: usize, n: usize, f: impl Fn(usize) -> [f64; 2]) -> [f64; 2] {
    let mut acc = [0.0; 2];
    for i in k * chunk..((k + 1) * chunk).min(n) {
        let v = f(i);
        acc[0] += v[0];
        acc[1] += v[1];
    }
    acc
}

/// The chunk sums added in chunk order.
#[inline]
pub fn in_chunk_order(chunk_sums: impl Iterator<Item = [f64; 2]>) -> [f64; 2] {
    let mut total = [0.0; 2];
    for s in chunk_sums {
        total[0] += s[0];
        total[1] += s[1];
    }
    total
}

impl Reducer {
    /// Σ_{i<n} f(i).
    pub fn sum(&mut self, n: usize, f: impl Fn(usize) -> f64 + Sync) -> f64 {
        self.sum2(n, |i| [f(i), 0.0])[0]
    }

    /// Two sums in one pass: (Σ f(i)[0], Σ f(i)[1]).
    pub fn sum2(&mut self, n: usize, f: impl Fn(usize) -> [f64; 2] + Sync) -> [f64; 2] {
        let n_chunks = n.div_ceil(CHUNK);
        self.partial.resize(n_chunks, [0.0; 2]);
        // the closure, not `&f` (see `gang::Crew::sum2`)
        #[allow(clippy::redundant_closure)]
        self.partial.par_iter_mut().enumerate().for_each(|(k, s)| *s = chunk_sum(k, CHUNK, n, |i| f(i)));
        in_chunk_order(self.partial.iter().copied())
    }

    /// max_{i<n} f(i) (order-independent, but kept in the same shape).
    pub fn max(&mut self, n: usize, f: impl Fn(usize) -> f64 + Sync) -> f64 {
        let n_chunks = n.div_ceil(CHUNK);
        self.partial.resize(n_chunks, [0.0; 2]);
        self.partial.par_iter_mut().enumerate().for_each(|(k, s)| {
            let mut m = f64::NEG_INFINITY;
            for i in k * CHUNK..((k + 1) * CHUNK).min(n) {
                m = m.max(f(i));
            }
            s[0] = m;
        });
        self.partial.iter().fold(f64::NEG_INFINITY, |m, s| m.max(s[0]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sums_are_bit_identical_on_one_and_three_threads() {
        // values of very different magnitudes make the sum order visible in the last bits
        let v: Vec<f64> = (0..100_000).map(|i| ((i * 7919) % 1000) as f64 * 1e-3 + if i % 97 == 0 { 1e8 } else { 0.0 }).collect();
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| Reducer::default().sum(v.len(), |i| v[i]))
        };
        assert_eq!(run(1).to_bits(), run(3).to_bits());
        let exact: f64 = v.chunks(CHUNK).map(|c| c.iter().sum::<f64>()).sum();
        assert_eq!(run(2).to_bits(), exact.to_bits());
    }
}
