//! [`super::pair_lanes`]'s four pairs written out in AVX instructions: the same IEEE
//! operations in the same order, lane by lane (nothing fused, divisions and square roots as
//! such), so each lane keeps the bits of the scalar contact; the unit test in
//! [`super::pair_lanes`] holds it to the bit with the portable and the AVX-512 kernels.
//!
//! Written with the compiler left to vectorise the lane arrays, the kernel came out as 1900
//! instructions, most of them spills, shuffles and scalar square roots; the selects of the
//! slip branch (lane by lane `if`s there) are blends here, and every quantity stays in a
//! 256-bit register.

use std::arch::x86_64::*;

use spillage_model::closure::contact::{PairConstants, SlipTest};
use spillage_model::particles::guards::MAX_OVERLAP_RATIO;
use spillage_model::particles::state::Vec3;

use super::arrays::ParticleArrays;
use super::neighbour_list::{PairEnergy, Touch};
use super::pair_lanes::{Lane, PairGroup};

/// Four 3-vectors, one per lane.
#[derive(Clone, Copy)]
pub(super) struct V {
    pub(super) x: __m256d,
    pub(super) y: __m256d,
    pub(super) z: __m256d,
}

/// Lane l of `f(l)`, as one register.
#[inline]
#[target_feature(enable = "avx")]
fn lanes(f: impl Fn(usize) -> f64) -> __m256d {
    _mm256_set_pd(f(3), f(2), f(1), f(0))
}

#[inline]
#[target_feature(enable = "avx")]
fn add(a: V, b: V) -> V {
    V { x: _mm256_add_pd(a.x, b.x), y: _mm256_add_pd(a.y, b.y), z: _mm256_add_pd(a.z, b.z) }
}

#[inline]
#[target_feature(enable = "avx")]
fn sub(a: V, b: V) -> V {
    V { x: _mm256_sub_pd(a.x, b.x), y: _mm256_sub_pd(a.y, b.y), z: _mm256_sub_pd(a.z, b.z) }
}

/// Each component times `s` (nalgebra's vector × scalar).
#[inline]
#[target_feature(enable = "avx")]
fn scale(a: V, s: __m256d) -> V {
    V { x: _mm256_mul_pd(a.x, s), y: _mm256_mul_pd(a.y, s), z: _mm256_mul_pd(a.z, s) }
}

#[inline]
#[target_feature(enable = "avx")]
fn divide(a: V, s: __m256d) -> V {
    V { x: _mm256_div_pd(a.x, s), y: _mm256_div_pd(a.y, s), z: _mm256_div_pd(a.z, s) }
}

/// nalgebra's order: (x x' + y y') + z z'.
#[inline]
#[target_feature(enable = "avx")]
fn dot(a: V, b: V) -> __m256d {
    _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(a.x, b.x), _mm256_mul_pd(a.y, b.y)), _mm256_mul_pd(a.z, b.z))
}

/// nalgebra's cross product: (a_y b_z − a_z b_y, a_z b_x − a_x b_z, a_x b_y − a_y b_x).
#[inline]
#[target_feature(enable = "avx")]
fn cross(a: V, b: V) -> V {
    V {
        x: _mm256_sub_pd(_mm256_mul_pd(a.y, b.z), _mm256_mul_pd(a.z, b.y)),
        y: _mm256_sub_pd(_mm256_mul_pd(a.z, b.x), _mm256_mul_pd(a.x, b.z)),
        z: _mm256_sub_pd(_mm256_mul_pd(a.x, b.y), _mm256_mul_pd(a.y, b.x)),
    }
}

/// The sign flipped (as scalar negation does).
#[inline]
#[target_feature(enable = "avx")]
fn negate(a: __m256d) -> __m256d {
    _mm256_xor_pd(a, _mm256_set1_pd(-0.0))
}

/// `when` lanes (all bits set) from `yes`, the others from `no`.
#[inline]
#[target_feature(enable = "avx")]
fn select(when: __m256d, yes: V, no: V) -> V {
    V { x: _mm256_blendv_pd(no.x, yes.x, when), y: _mm256_blendv_pd(no.y, yes.y, when), z: _mm256_blendv_pd(no.z, yes.z, when) }
}

/// Rows `k` of `v` (each below its length), one register per component: each row's x, y, z
/// loaded at once (a masked load, which reads nothing past the row) and the four transposed,
/// 4 loads and 7 shuffles where one load per component and lane took 12 and 9.
///
/// # Safety
/// The processor has AVX, and every `k` is below `v`'s length (called from the kernel only,
/// which checks its indices once; written without `target_feature` so that it is always
/// inlined there: a separate call returned its registers through memory).
#[inline(always)]
pub(super) unsafe fn gather_rows(v: &[Vec3], k: [usize; 4]) -> V {
    // SAFETY: the processor has AVX and row i < len is three contiguous f64 (nalgebra's array
    // storage; this function's contract), and the mask reads only those three
    unsafe {
        let row = |i: usize| _mm256_maskload_pd(v.as_ptr().add(i) as *const f64, xyz());
        let [x, y, z, _] = transpose(row(k[0]), row(k[1]), row(k[2]), row(k[3]));
        V { x, y, z }
    }
}

/// The four pairs' contact histories: tangential overlaps and damping ratios (each `Touch`
/// is exactly four doubles, loaded at once and transposed).
///
/// # Safety
/// The processor has AVX (it checks the length itself; written without `target_feature` for
/// the reason [`gather_rows`] gives).
#[inline(always)]
pub(super) unsafe fn gather_touch(touch: &[Touch]) -> (V, __m256d) {
    assert!(touch.len() >= 4);
    // SAFETY: l < 4 ≤ len, and a Touch is four contiguous f64 (repr(C): a Vec3, then an f64)
    let row = |l: usize| unsafe { _mm256_loadu_pd(touch.as_ptr().add(l) as *const f64) };
    // SAFETY: as above
    let [x, y, z, damping_ratio] = unsafe { transpose(row(0), row(1), row(2), row(3)) };
    (V { x, y, z }, damping_ratio)
}

/// The mask of a row's x, y and z (not the fourth double) for masked loads and stores.
#[inline]
#[target_feature(enable = "avx")]
pub(super) fn xyz() -> __m256i {
    _mm256_set_epi64x(0, -1, -1, -1)
}

/// Rows (a₀ a₁ a₂ a₃), (b…), (c…), (d…) into columns (a₀ b₀ c₀ d₀), (a₁ …), (a₂ …), (a₃ …).
///
/// # Safety
/// The processor has AVX.
#[inline(always)]
pub(super) unsafe fn transpose(a: __m256d, b: __m256d, c: __m256d, d: __m256d) -> [__m256d; 4] {
    // SAFETY: the processor has AVX (this function's contract)
    unsafe {
        let (ab_even, ab_odd) = (_mm256_unpacklo_pd(a, b), _mm256_unpackhi_pd(a, b));
        let (cd_even, cd_odd) = (_mm256_unpacklo_pd(c, d), _mm256_unpackhi_pd(c, d));
        [
            _mm256_permute2f128_pd::<0x20>(ab_even, cd_even),
            _mm256_permute2f128_pd::<0x20>(ab_odd, cd_odd),
            _mm256_permute2f128_pd::<0x31>(ab_even, cd_even),
            _mm256_permute2f128_pd::<0x31>(ab_odd, cd_odd),
        ]
    }
}

#[inline]
#[target_feature(enable = "avx")]
fn to_array(v: __m256d) -> [f64; 4] {
    let mut a = [0.0; 4];
    // SAFETY: `a` holds four f64 (unaligned store).
    unsafe { _mm256_storeu_pd(a.as_mut_ptr(), v) };
    a
}

/// [`super::pair_lanes::in_lanes`] in AVX instructions (the caller checked the processor has
/// them).
#[inline]
#[target_feature(enable = "avx")]
pub fn four_pairs_avx(group: PairGroup, arrays: &ParticleArrays, dt: f64, measure_energy: bool) -> [Lane; 4] {
    let PairGroup { pairs, constants, touch, energy, out } = group;
    let (a, b) = ([0, 1, 2, 3].map(|l| pairs[l].a as usize), [0, 1, 2, 3].map(|l| pairs[l].b as usize));
    // the group's indices checked once, in place of a check per read (they were a tenth of
    // the kernel's instructions)
    let n = arrays.radius.len().min(arrays.position.len()).min(arrays.velocity.len()).min(arrays.spin.len());
    let below = |k: [usize; 4]| (k[0] < n) & (k[1] < n) & (k[2] < n) & (k[3] < n);
    assert!(below(a) & below(b) & (touch.len() >= 4) & (energy.len() >= 4) & (out.len() >= 4));
    // SAFETY: k is one of the group's indices, below every array's length (checked above)
    let radius = |k: usize| unsafe { *arrays.radius.get_unchecked(k) };
    let c = [0, 1, 2, 3].map(|l| &constants[pairs[l].constants as usize]);
    // a bed of one size and material has one set of constants: one load each, not four
    let shared = pairs[1..4].iter().all(|p| p.constants == pairs[0].constants);
    let constant = |of: fn(&PairConstants) -> f64| if shared { _mm256_set1_pd(of(c[0])) } else { lanes(|l| of(c[l])) };
    let zero = _mm256_setzero_pd();
    // SAFETY (the gathers): this function runs where the processor has AVX, and the indices
    // are below every array's length (checked above)
    let (old_delta, damping_ratio) = unsafe { gather_touch(touch) };
    let ra = lanes(|l| radius(a[l]));
    let rb = lanes(|l| radius(b[l]));
    let offset = unsafe { sub(gather_rows(&arrays.position, b), gather_rows(&arrays.position, a)) };
    let distance = _mm256_sqrt_pd(dot(offset, offset));
    let reach = _mm256_add_pd(ra, rb);
    // each lane's outcome, as the scalar tests take it: apart and not touched before; or
    // touching, touched before and not near a fault (done below); else left to the scalar code
    let touching = _mm256_cmp_pd::<_CMP_LT_OQ>(distance, reach);
    let active = _mm256_cmp_pd::<_CMP_ORD_Q>(damping_ratio, damping_ratio);
    if _mm256_movemask_pd(_mm256_or_pd(touching, active)) == 0 {
        // four pairs apart, none touched before: the contact law would be computed for nothing
        // (in the settled 10⁴ bed's run: 1472 → 1396 instructions a particle-step, 8 % less time)
        for entry in out.iter_mut().take(4) {
            entry.touching = false;
        }
        return [Lane::Apart; 4];
    }
    let overlap = _mm256_sub_pd(reach, distance);

    let normal = divide(offset, distance);
    let arm_a = scale(normal, ra);
    let arm_b = scale(normal, negate(rb));
    let v_rel = sub(
        add(unsafe { gather_rows(&arrays.velocity, a) }, cross(unsafe { gather_rows(&arrays.spin, a) }, arm_a)),
        add(unsafe { gather_rows(&arrays.velocity, b) }, cross(unsafe { gather_rows(&arrays.spin, b) }, arm_b)),
    );

    // hertz_mindlin_force, lane by lane
    let approach_speed = dot(v_rel, normal);
    let u_n = scale(normal, approach_speed);
    let u_t = sub(v_rel, u_n);
    // max(δ, 0) as f64::max takes it for every δ a kept lane can have (δ > 0)
    let root = _mm256_sqrt_pd(_mm256_max_pd(overlap, zero));
    let eta = _mm256_mul_pd(_mm256_mul_pd(damping_ratio, constant(|c| c.damping_scale)), _mm256_sqrt_pd(root));
    let f_n = sub(scale(normal, _mm256_mul_pd(constant(|c| -c.normal_stiffness), _mm256_mul_pd(overlap, root))), scale(u_n, eta));
    let old_length_sq = dot(old_delta, old_delta);
    let in_plane = sub(old_delta, scale(normal, dot(old_delta, normal)));
    let in_plane_length_sq = dot(in_plane, in_plane);
    // ×1 keeps the bits of a vector the scalar code leaves alone
    let one = _mm256_set1_pd(1.0);
    let rotated = _mm256_cmp_pd::<_CMP_GT_OQ>(in_plane_length_sq, zero);
    let keep_length = _mm256_blendv_pd(one, _mm256_sqrt_pd(_mm256_div_pd(old_length_sq, in_plane_length_sq)), rotated);
    let delta = add(scale(in_plane, keep_length), scale(u_t, _mm256_set1_pd(dt)));
    let spring = _mm256_mul_pd(constant(|c| c.tangential_stiffness), root);
    let spring_force = scale(delta, negate(spring));
    let trial = sub(spring_force, scale(u_t, eta));
    let friction = constant(|c| c.friction);
    let f_n_sq = dot(f_n, f_n);
    let limit_sq = _mm256_mul_pd(_mm256_mul_pd(friction, friction), f_n_sq);
    let trial_sq = dot(trial, trial);
    let spring_sq = dot(spring_force, spring_force);

    // (T3.95) slip branch, computed in every lane and kept where the Coulomb limit is exceeded
    let thesis = constant(|c| if c.slip_test == SlipTest::Thesis { f64::from_bits(u64::MAX) } else { 0.0 });
    let exceeds = _mm256_blendv_pd(_mm256_cmp_pd::<_CMP_GT_OQ>(spring_sq, limit_sq), _mm256_cmp_pd::<_CMP_GT_OQ>(trial_sq, limit_sq), thesis);
    // a group with no lane sliding (most of a settled bed's) keeps δ_t and the trial force,
    // as each lane would (a rescale by 1 keeps the bits)
    let (delta, tangential) =
        if _mm256_movemask_pd(exceeds) == 0 { (delta, trial) } else { slip(exceeds, thesis, friction, f_n_sq, trial, trial_sq, delta, spring) };
    let force = add(f_n, tangential);
    let torque_a = cross(arm_a, tangential);
    let minus = V { x: negate(tangential.x), y: negate(tangential.y), z: negate(tangential.z) };
    let torque_b = cross(arm_b, minus);

    let elastic = if measure_energy { to_array(_mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(0.4), _mm256_sqrt_pd(f_n_sq)), overlap)) } else { [0.0; 4] };
    let all = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
    let limit = _mm256_mul_pd(_mm256_set1_pd(MAX_OVERLAP_RATIO), _mm256_min_pd(ra, rb));
    let near_fault = _mm256_or_pd(_mm256_cmp_pd::<_CMP_EQ_OQ>(distance, zero), _mm256_cmp_pd::<_CMP_GT_OQ>(overlap, limit));
    let done = _mm256_movemask_pd(_mm256_andnot_pd(near_fault, _mm256_and_pd(touching, active)));
    let apart = _mm256_movemask_pd(_mm256_andnot_pd(_mm256_or_pd(touching, active), all));
    // SAFETY (the transposes): this function runs where the processor has AVX
    let (history, force, torque_a, torque_b) = unsafe {
        (
            transpose(delta.x, delta.y, delta.z, damping_ratio),
            transpose(force.x, force.y, force.z, zero),
            transpose(torque_a.x, torque_a.y, torque_a.z, zero),
            transpose(torque_b.x, torque_b.y, torque_b.z, zero),
        )
    };
    let overlap = to_array(overlap);
    let mut result = [Lane::Scalar; 4];
    for l in 0..4 {
        if apart & (1 << l) != 0 {
            out[l].touching = false;
            result[l] = Lane::Apart;
        } else if done & (1 << l) != 0 {
            // SAFETY: l < 4 ≤ both lengths (checked above); a Touch is its δ_t and damping
            // ratio, four f64, and a PairForce nine f64 from its start (both repr(C)): force and
            // torque on a are stored four at a time, each over the next one's first, and the
            // torque on b three, before the flag
            unsafe {
                _mm256_storeu_pd(touch.as_mut_ptr().add(l) as *mut f64, history[l]);
                let entry = out.as_mut_ptr().add(l) as *mut f64;
                _mm256_storeu_pd(entry, force[l]);
                _mm256_storeu_pd(entry.add(3), torque_a[l]);
                _mm256_maskstore_pd(entry.add(6), xyz(), torque_b[l]);
            }
            out[l].touching = true;
            if measure_energy {
                energy[l] = PairEnergy { overlap: overlap[l], elastic: elastic[l], placed: 0.0 };
            }
            result[l] = Lane::Done;
        }
    }
    result
}

/// (T3.95) the slip branch of every lane, kept where the Coulomb limit is exceeded: the new
/// tangential overlap and force.
#[allow(clippy::too_many_arguments)]
#[inline]
#[target_feature(enable = "avx")]
fn slip(exceeds: __m256d, thesis: __m256d, friction: __m256d, f_n_sq: __m256d, trial: V, trial_sq: __m256d, delta: V, spring: __m256d) -> (V, V) {
    let (zero, one) = (_mm256_setzero_pd(), _mm256_set1_pd(1.0));
    let limit = _mm256_mul_pd(friction, _mm256_sqrt_pd(f_n_sq));
    let trial_length = _mm256_sqrt_pd(trial_sq);
    let direction = select(_mm256_cmp_pd::<_CMP_GT_OQ>(trial_length, zero), divide(trial, trial_length), V { x: zero, y: zero, z: zero });
    let sliding_force = scale(direction, limit);
    let delta_length = _mm256_sqrt_pd(dot(delta, delta));
    let spring_length = _mm256_mul_pd(spring, delta_length);
    let capped = _mm256_and_pd(
        _mm256_and_pd(_mm256_cmp_pd::<_CMP_GT_OQ>(spring, zero), _mm256_cmp_pd::<_CMP_GT_OQ>(delta_length, zero)),
        _mm256_cmp_pd::<_CMP_GT_OQ>(spring_length, limit),
    );
    let rescaled = _mm256_and_pd(_mm256_and_pd(exceeds, thesis), capped);
    let rescale = _mm256_blendv_pd(one, _mm256_div_pd(limit, spring_length), rescaled);
    // OpenFOAM's test resets δ_t on slip (to +0, which a product with 0 would not give)
    let reset = _mm256_andnot_pd(thesis, exceeds);
    let delta = select(reset, V { x: zero, y: zero, z: zero }, scale(delta, rescale));
    let tangential = select(exceeds, sliding_force, trial);
    (delta, tangential)
}
