//! The median the step reports as the particles' settling velocity.

/// The median of `values` (the mean of the middle two for an even count); `values` not empty.
///
/// The middle order statistics are selected, not the whole list sorted (a run's 10⁴ particles
/// were sorted at every step). Two values equal under `total_cmp` have the same bits, so the
/// selected values, and the mean of the two, are those of a sort.
pub fn median(mut values: Vec<f64>) -> f64 {
    let n = values.len();
    let (below, middle, _) = values.select_nth_unstable_by(n / 2, f64::total_cmp);
    if n % 2 == 1 {
        *middle
    } else {
        let lower = below.iter().copied().max_by(f64::total_cmp).expect("an even count above 0 leaves one below the middle");
        0.5 * (lower + *middle)
    }
}

#[cfg(test)]
mod tests {
    use super::median;

    /// The median as a sort gives it.
    fn sorted_median(mut values: Vec<f64>) -> f64 {
        values.sort_by(f64::total_cmp);
        let n = values.len();
        if n % 2 == 1 {
            values[n / 2]
        } else {
            0.5 * (values[n / 2 - 1] + values[n / 2])
        }
    }

    /// The same bits as a sort, for odd and even counts, with repeated values, both zeros and
    /// values a bit apart.
    #[test]
    fn the_same_bits_as_a_sort() {
        let mut state = 7u64;
        let mut next = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for n in 1..200 {
            let values: Vec<f64> = (0..n)
                .map(|_| match (next() * 5.0) as u32 {
                    0 => 0.0,
                    1 => -0.0,
                    2 => 0.25,
                    3 => f64::from_bits(0.25f64.to_bits() + 1),
                    _ => next() - 0.5,
                })
                .collect();
            assert_eq!(median(values.clone()).to_bits(), sorted_median(values.clone()).to_bits(), "{values:?}");
        }
    }
}
