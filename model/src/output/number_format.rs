//! Text form of a float that reads back to the identical bit pattern.

/// Shortest decimal text that parses back to exactly `value` (Rust's float formatting emits the
/// shortest round-tripping digit string). Plain notation for magnitudes in [1e-4, 1e15), where it
/// is short and readable; exponent notation outside, where plain notation would be long.
/// Non-finite values are the callers' business: every writer refuses them before formatting.
pub fn format_f64(value: f64) -> String {
    let magnitude = value.abs();
    if magnitude == 0.0 || (1e-4..1e15).contains(&magnitude) {
        format!("{value}")
    } else {
        format!("{value:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_bit_exactly_over_many_magnitudes() {
        let mut samples = vec![
            0.0,
            -0.0,
            0.1,
            1.0 / 3.0,
            -2.5e-300,
            f64::MIN_POSITIVE,
            f64::MAX,
            f64::MIN,
            f64::EPSILON,
            5e-324,
            123456789.12345679,
            1e15,
            9.999999999999999e14,
            1e-4,
            9.99999e-5,
        ];
        // A deterministic spread of awkward values: x_{k+1} = x_k * 1.37 + 1/7, both signs.
        let mut x = 1.0e-12_f64;
        for _ in 0..200 {
            samples.push(x);
            samples.push(-x);
            x = x * 1.37 + 1.0 / 7.0 * x.sqrt();
        }
        for v in samples {
            let text = format_f64(v);
            let back: f64 = text.parse().unwrap();
            assert_eq!(back.to_bits(), v.to_bits(), "{v:?} -> {text}");
        }
    }

    #[test]
    fn uses_plain_notation_for_ordinary_magnitudes() {
        assert_eq!(format_f64(0.25), "0.25");
        assert_eq!(format_f64(-1500.0), "-1500");
        assert_eq!(format_f64(1e-7), "1e-7");
        assert_eq!(format_f64(2.5e20), "2.5e20");
    }
}
