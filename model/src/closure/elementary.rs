//! e^x and ln x for the drag law (fluid-dem-model.md §5.2, §5.5), written out with additions,
//! multiplications, divisions, comparisons and bit moves only, so that:
//!
//! - **a particle's drag law vectorises.** Inlined into a loop over particles, these compile
//!   to SIMD lanes, where a call into the C library (`exp`, `log`, `pow`) is one particle at a
//!   time. The fast particle phase evaluates eight particles' drag laws at once with them
//!   (`fast/src/dem/drag_lanes.rs`).
//! - **the bits do not depend on the lanes or the machine.** Only correctly rounded IEEE-754
//!   operations are used, and Rust never fuses a multiplication and an addition on its own,
//!   so one particle's result is the same bit for bit in a lane of any width and in the
//!   reference's scalar code; glibc instead picks its `exp`, `log` and `pow` by the CPU
//!   (`__ieee754_pow_fma` with FMA, another code path without).
//!
//! Both are within 1 unit in the last place of the standard library's (itself within 1 of the
//! correctly rounded value): the tests compare them at about 2·10⁶ points each, spread over
//! every exponent of `f64` and densely where the drag law takes them, and at the edges.

/// ln 2 in two parts (fdlibm's): n·`LN2_HI` is exact for |n| < 2¹¹, so the reduction
/// x − n ln 2 loses nothing for the exponents of finite doubles.
const LN2_HI: f64 = f64::from_bits(0x3fe6_2e42_fee0_0000);
const LN2_LO: f64 = f64::from_bits(0x3dea_39ef_3579_3c76);
/// 1.5·2⁵²: a double in [2⁵², 2⁵³) has unit spacing, so adding this rounds to an integer, and the
/// integer is the low bits of the sum.
const ROUND_TO_INTEGER: f64 = 6_755_399_441_055_744.0;

/// e^x. NaN gives NaN, +∞ (and anything above ln of the largest double) gives +∞, −∞ gives 0,
/// results below the smallest normal double are rounded to subnormals.
#[inline(always)]
pub fn exp(x: f64) -> f64 {
    // beyond these the result is ∞ or 0 anyway; the clamp keeps 2ⁿ representable as two
    // factors (a NaN stays NaN)
    let x = x.clamp(-746.0, 710.0);
    // x = n ln 2 + r, |r| ≤ ½ ln 2
    let shifted = x * std::f64::consts::LOG2_E + ROUND_TO_INTEGER;
    let n = shifted - ROUND_TO_INTEGER;
    let r = (x - n * LN2_HI) - n * LN2_LO;
    // e^r by its Taylor series to r¹³: the first term left out, r¹⁴/14! ≈ 4e-18 for
    // |r| ≤ 0.347, is below half a unit in the last place
    let mut p = 1.0 / 6_227_020_800.0; // 1/13!
    for factorial in [479_001_600.0, 39_916_800.0, 3_628_800.0, 362_880.0, 40_320.0, 5_040.0, 720.0, 120.0, 24.0, 6.0, 2.0, 1.0, 1.0] {
        p = p * r + 1.0 / factorial;
    }
    // 2ⁿ as two normal powers of two: n runs from −1 077 to 1 025 after the clamp, beyond
    // the normal exponents, and the two products round once, where the result does
    let n = (shifted.to_bits() as i64).wrapping_sub(ROUND_TO_INTEGER.to_bits() as i64);
    let half = n >> 1;
    let power = |k: i64| f64::from_bits(((k + 1023) as u64) << 52);
    p * power(half) * power(n - half)
}

/// ln x. NaN and x < 0 give NaN, ±0 gives −∞, +∞ gives +∞; subnormal x are first scaled
/// (exactly) into the normal range.
#[inline(always)]
pub fn ln(x: f64) -> f64 {
    // subnormals scaled by 2⁵⁴ into the normal range
    let subnormal = x < f64::MIN_POSITIVE;
    let y = if subnormal { x * 18_014_398_509_481_984.0 } else { x };
    let bits = y.to_bits();
    // y = 2^e m with m ∈ [1, 2), then m ∈ [√½, √2) so that ln m is small; e as a double by
    // placing the biased exponent in the mantissa of 2⁵² (an integer conversion would not
    // vectorise without AVX-512)
    let biased = f64::from_bits(0x4330_0000_0000_0000 | ((bits >> 52) & 0x7ff)) - (4_503_599_627_370_496.0 + 1023.0);
    let m = f64::from_bits((bits & 0x000f_ffff_ffff_ffff) | 0x3ff0_0000_0000_0000);
    let big = m > std::f64::consts::SQRT_2;
    let m = if big { 0.5 * m } else { m };
    let k = biased + if big { 1.0 } else { 0.0 } - if subnormal { 54.0 } else { 0.0 };
    // ln(1 + f) = f − f²/2 + s (f²/2 + R(s²)), s = f/(2 + f), the form of fdlibm's e_log.c;
    // R(z) = Σ 2z^k/(2k+1) is the series of 2 atanh s − 2s over s, |s| ≤ 0.172, z ≤ 0.0295:
    // its first term left out, 2z¹²/25 < 4e-20, is below the last place
    let f = m - 1.0; // exact (m within a factor 2 of 1)
    let half_f2 = 0.5 * f * f;
    let s = f / (2.0 + f);
    let z = s * s;
    let mut r = 2.0 / 23.0;
    for odd in [21.0, 19.0, 17.0, 15.0, 13.0, 11.0, 9.0, 7.0, 5.0, 3.0] {
        r = r * z + 2.0 / odd;
    }
    r *= z;
    let value = k * LN2_HI - ((half_f2 - (s * (half_f2 + r) + k * LN2_LO)) - f);
    if x > 0.0 && x < f64::INFINITY {
        value
    } else if x == 0.0 {
        f64::NEG_INFINITY
    } else if x == f64::INFINITY {
        f64::INFINITY
    } else {
        f64::NAN
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance in units in the last place between two finite doubles of one sign.
    fn ulps(a: f64, b: f64) -> u64 {
        (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs()
    }

    /// A reproducible spread of points: a 64-bit linear congruential sequence.
    fn points(n: usize, low: f64, high: f64) -> impl Iterator<Item = f64> {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        (0..n).map(move |_| {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            low + (high - low) * ((state >> 11) as f64 / (1u64 << 53) as f64)
        })
    }

    /// Over the normal range and the drag law's: at most 1 ulp from the standard library's
    /// (measured: 1 at about a tenth of the points, 0 elsewhere).
    #[test]
    fn exp_within_one_ulp() {
        let mut worst = 0;
        for x in points(1_000_000, -708.0, 709.0).chain(points(1_000_000, -30.0, 30.0)).chain(points(100_000, -1e-6, 1e-6)) {
            worst = worst.max(ulps(exp(x), x.exp()));
        }
        assert!(worst <= 1, "exp: {worst} ulp");
        for x in [0.0, -0.0, 1.0, -1.0, 0.5 * std::f64::consts::LN_2, 709.78, -708.39] {
            assert!(ulps(exp(x), x.exp()) <= 1, "exp({x}) = {} against {}", exp(x), x.exp());
        }
        assert_eq!(exp(0.0), 1.0, "a lone particle's hindrance α^0 is exactly 1");
    }

    /// Subnormal results, overflow and the special values.
    #[test]
    fn exp_at_the_edges() {
        for x in [-710.0, -720.0, -740.0, -744.0] {
            let (a, b) = (exp(x), x.exp());
            // a subnormal's last place is the smallest subnormal, so compare absolutely (one
            // such place), and a normal result within one relative ulp (2.2e-16, rounded up)
            assert!((a - b).abs() <= 4.9e-324_f64.max(b * 2.3e-16), "exp({x}) = {a:e} against {b:e}");
        }
        assert_eq!(exp(-746.0), 0.0);
        assert_eq!(exp(-1e300), 0.0);
        assert_eq!(exp(f64::NEG_INFINITY), 0.0);
        assert_eq!(exp(710.0), f64::INFINITY);
        assert_eq!(exp(f64::INFINITY), f64::INFINITY);
        assert!(exp(f64::NAN).is_nan());
    }

    #[test]
    fn ln_within_one_ulp() {
        let mut worst = 0;
        // every exponent, subnormals included: 2^e with e uniform in [−1074, 1024)
        let everywhere = points(200_000, -1074.0, 1024.0).map(f64::exp2);
        for x in points(1_000_000, 1e-3, 1e6).chain(points(1_000_000, 0.5, 2.0)).chain(everywhere) {
            worst = worst.max(ulps(ln(x), x.ln()));
        }
        assert!(worst <= 1, "ln: {worst} ulp");
        assert_eq!(ln(1.0).to_bits(), 0.0f64.to_bits(), "ln 1 = +0");
        // near 1, where ln x → 0 and a careless form loses every digit
        for x in [1.0 + f64::EPSILON, 1.0 - f64::EPSILON / 2.0, 1.000_001, 0.999_999] {
            assert!(ulps(ln(x), x.ln()) <= 1, "ln({x}) = {} against {}", ln(x), x.ln());
        }
    }

    #[test]
    fn ln_at_the_edges() {
        for x in [f64::MIN_POSITIVE, f64::MIN_POSITIVE / 3.0, 4.9e-324, f64::MAX] {
            assert!(ulps(ln(x), x.ln()) <= 1, "ln({x:e}) = {} against {}", ln(x), x.ln());
        }
        assert_eq!(ln(0.0), f64::NEG_INFINITY);
        assert_eq!(ln(-0.0), f64::NEG_INFINITY);
        assert_eq!(ln(f64::INFINITY), f64::INFINITY);
        assert!(ln(-1.0).is_nan());
        assert!(ln(f64::NAN).is_nan());
        assert!(ln(f64::NEG_INFINITY).is_nan());
    }
}
