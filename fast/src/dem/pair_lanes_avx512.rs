//! [`super::pair_lanes_avx`]'s kernel eight pairs wide, in AVX-512 registers: the same IEEE
//! operations in the same order, lane by lane (nothing fused, divisions and square roots as
//! such), so each lane keeps the bits of the scalar contact; the unit test in
//! [`super::pair_lanes`] holds it to the bit with the others.
//!
//! Why eight: a group's contact law is one long chain of dependent operations (a square root
//! for the distance, a division for the normal, two more square roots for the Hertz stiffness
//! and damping, one for the kept tangential length, then the Coulomb test), and the processor
//! works through a group of four pairs mostly waiting on that chain, the next group's
//! instructions too far behind to overlap it. Eight lanes take one chain for twice the pairs,
//! with half the arithmetic per pair (the gathers, transposes and row stores stay as many).
//! Measured on the 10⁴ settling bed (`cases/bench/settle_box_10k.toml`, one thread, AMD EPYC
//! with AVX-512): 7 % less time than the AVX kernel (median of 8 interleaved pairs of runs;
//! 6 % at 10⁵), so the chain's latency, not the instruction count, bounded the four-lane
//! loop. (`benches/instructions.sh` cannot count this kernel: valgrind does not run AVX-512,
//! so under it the loop takes the AVX kernel.)

use std::arch::x86_64::*;

use spillage_model::closure::contact::{PairConstants, SlipTest};
use spillage_model::particles::guards::MAX_OVERLAP_RATIO;
use spillage_model::particles::state::Vec3;

use super::arrays::ParticleArrays;
use super::neighbour_list::PairEnergy;
use super::pair_lanes::{Lane, PairGroup};
use super::pair_lanes_avx as avx;

/// Eight 3-vectors, one per lane.
#[derive(Clone, Copy)]
struct V {
    x: __m512d,
    y: __m512d,
    z: __m512d,
}

/// Lane l of `f(l)`, as one register.
#[inline]
#[target_feature(enable = "avx512f")]
fn lanes(f: impl Fn(usize) -> f64) -> __m512d {
    _mm512_set_pd(f(7), f(6), f(5), f(4), f(3), f(2), f(1), f(0))
}

#[inline]
#[target_feature(enable = "avx512f")]
fn add(a: V, b: V) -> V {
    V { x: _mm512_add_pd(a.x, b.x), y: _mm512_add_pd(a.y, b.y), z: _mm512_add_pd(a.z, b.z) }
}

#[inline]
#[target_feature(enable = "avx512f")]
fn sub(a: V, b: V) -> V {
    V { x: _mm512_sub_pd(a.x, b.x), y: _mm512_sub_pd(a.y, b.y), z: _mm512_sub_pd(a.z, b.z) }
}

/// Each component times `s` (nalgebra's vector × scalar).
#[inline]
#[target_feature(enable = "avx512f")]
fn scale(a: V, s: __m512d) -> V {
    V { x: _mm512_mul_pd(a.x, s), y: _mm512_mul_pd(a.y, s), z: _mm512_mul_pd(a.z, s) }
}

#[inline]
#[target_feature(enable = "avx512f")]
fn divide(a: V, s: __m512d) -> V {
    V { x: _mm512_div_pd(a.x, s), y: _mm512_div_pd(a.y, s), z: _mm512_div_pd(a.z, s) }
}

/// nalgebra's order: (x x' + y y') + z z'.
#[inline]
#[target_feature(enable = "avx512f")]
fn dot(a: V, b: V) -> __m512d {
    _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(a.x, b.x), _mm512_mul_pd(a.y, b.y)), _mm512_mul_pd(a.z, b.z))
}

/// nalgebra's cross product: (a_y b_z − a_z b_y, a_z b_x − a_x b_z, a_x b_y − a_y b_x).
#[inline]
#[target_feature(enable = "avx512f")]
fn cross(a: V, b: V) -> V {
    V {
        x: _mm512_sub_pd(_mm512_mul_pd(a.y, b.z), _mm512_mul_pd(a.z, b.y)),
        y: _mm512_sub_pd(_mm512_mul_pd(a.z, b.x), _mm512_mul_pd(a.x, b.z)),
        z: _mm512_sub_pd(_mm512_mul_pd(a.x, b.y), _mm512_mul_pd(a.y, b.x)),
    }
}

/// The sign flipped (as scalar negation does; an integer xor, which AVX-512 F has for 512 bits).
#[inline]
#[target_feature(enable = "avx512f")]
fn negate(a: __m512d) -> __m512d {
    _mm512_castsi512_pd(_mm512_xor_si512(_mm512_castpd_si512(a), _mm512_set1_epi64(i64::MIN)))
}

/// `when` lanes from `yes`, the others from `no`.
#[inline]
#[target_feature(enable = "avx512f")]
fn select(when: __mmask8, yes: V, no: V) -> V {
    V { x: _mm512_mask_blend_pd(when, no.x, yes.x), y: _mm512_mask_blend_pd(when, no.y, yes.y), z: _mm512_mask_blend_pd(when, no.z, yes.z) }
}

/// Two halves of four lanes as one register of eight (`low` lanes 0–3).
#[inline]
#[target_feature(enable = "avx512f")]
fn join(low: __m256d, high: __m256d) -> __m512d {
    _mm512_insertf64x4::<1>(_mm512_castpd256_pd512(low), high)
}

/// Lanes 0–3 and 4–7.
#[inline]
#[target_feature(enable = "avx512f")]
fn halves(v: __m512d) -> (__m256d, __m256d) {
    (_mm512_castpd512_pd256(v), _mm512_extractf64x4_pd::<1>(v))
}

/// Rows `k` of `v`, each below its length, one register per component (four rows at a time
/// by [`avx::gather_rows`]).
///
/// # Safety
/// The processor has AVX-512 F, and every `k` is below `v`'s length (written without
/// `target_feature` so that it is always inlined into the kernel, as the AVX gathers are).
#[inline(always)]
unsafe fn gather_rows(v: &[Vec3], k: [usize; 8]) -> V {
    // SAFETY: AVX-512 F implies AVX; the rows are in bounds (this function's contract)
    unsafe {
        let low = avx::gather_rows(v, [k[0], k[1], k[2], k[3]]);
        let high = avx::gather_rows(v, [k[4], k[5], k[6], k[7]]);
        V { x: join(low.x, high.x), y: join(low.y, high.y), z: join(low.z, high.z) }
    }
}

/// Lane l of `v` as an array.
#[inline]
#[target_feature(enable = "avx512f")]
fn to_array(v: __m512d) -> [f64; 8] {
    let mut a = [0.0; 8];
    // SAFETY: `a` holds eight f64 (unaligned store).
    unsafe { _mm512_storeu_pd(a.as_mut_ptr(), v) };
    a
}

/// Rows (x_l, y_l, z_l, w_l) of the eight lanes (four doubles each: a row store's width).
///
/// # Safety
/// The processor has AVX-512 F (as [`gather_rows`], without `target_feature`).
#[inline(always)]
unsafe fn rows(x: __m512d, y: __m512d, z: __m512d, w: __m512d) -> [__m256d; 8] {
    // SAFETY: AVX-512 F implies AVX (this function's contract)
    unsafe {
        let ((x0, x1), (y0, y1), (z0, z1), (w0, w1)) = (halves(x), halves(y), halves(z), halves(w));
        let [r0, r1, r2, r3] = avx::transpose(x0, y0, z0, w0);
        let [r4, r5, r6, r7] = avx::transpose(x1, y1, z1, w1);
        [r0, r1, r2, r3, r4, r5, r6, r7]
    }
}

/// [`super::pair_lanes::in_lanes`] for eight pairs, in AVX-512 instructions (the caller checked
/// the processor has AVX-512 F).
#[inline]
#[target_feature(enable = "avx512f")]
pub fn eight_pairs_avx512(group: PairGroup, arrays: &ParticleArrays, dt: f64, measure_energy: bool) -> [Lane; 8] {
    let PairGroup { pairs, constants, touch, energy, out } = group;
    let lane_indices: [usize; 8] = [0, 1, 2, 3, 4, 5, 6, 7];
    let (a, b) = (lane_indices.map(|l| pairs[l].a as usize), lane_indices.map(|l| pairs[l].b as usize));
    // the group's indices checked once, in place of a check per read
    let n = arrays.radius.len().min(arrays.position.len()).min(arrays.velocity.len()).min(arrays.spin.len());
    let below = |k: [usize; 8]| k.iter().fold(true, |ok, &k| ok & (k < n));
    assert!(below(a) & below(b) & (touch.len() >= 8) & (energy.len() >= 8) & (out.len() >= 8));
    // SAFETY: k is one of the group's indices, below every array's length (checked above)
    let radius = |k: usize| unsafe { *arrays.radius.get_unchecked(k) };
    let c = lane_indices.map(|l| &constants[pairs[l].constants as usize]);
    // a bed of one size and material has one set of constants: one load each, not eight
    let shared = pairs[1..8].iter().all(|p| p.constants == pairs[0].constants);
    let constant = |of: fn(&PairConstants) -> f64| if shared { _mm512_set1_pd(of(c[0])) } else { lanes(|l| of(c[l])) };
    let zero = _mm512_setzero_pd();
    // SAFETY (the gathers): this function runs where the processor has AVX-512 F, and the
    // indices are below every array's length (checked above); touch holds at least eight
    let (old_delta, damping_ratio) = unsafe {
        let (low, low_ratio) = avx::gather_touch(&touch[..4]);
        let (high, high_ratio) = avx::gather_touch(&touch[4..8]);
        (V { x: join(low.x, high.x), y: join(low.y, high.y), z: join(low.z, high.z) }, join(low_ratio, high_ratio))
    };
    let ra = lanes(|l| radius(a[l]));
    let rb = lanes(|l| radius(b[l]));
    let offset = unsafe { sub(gather_rows(&arrays.position, b), gather_rows(&arrays.position, a)) };
    let distance = _mm512_sqrt_pd(dot(offset, offset));
    let reach = _mm512_add_pd(ra, rb);
    // each lane's outcome, as the scalar tests take it (see the AVX kernel)
    let touching = _mm512_cmp_pd_mask::<_CMP_LT_OQ>(distance, reach);
    let active = _mm512_cmp_pd_mask::<_CMP_ORD_Q>(damping_ratio, damping_ratio);
    if touching | active == 0 {
        // eight pairs apart, none touched before: the contact law would be computed for nothing
        for entry in out.iter_mut().take(8) {
            entry.touching = false;
        }
        return [Lane::Apart; 8];
    }
    let overlap = _mm512_sub_pd(reach, distance);

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
    let root = _mm512_sqrt_pd(_mm512_max_pd(overlap, zero));
    let eta = _mm512_mul_pd(_mm512_mul_pd(damping_ratio, constant(|c| c.damping_scale)), _mm512_sqrt_pd(root));
    let f_n = sub(scale(normal, _mm512_mul_pd(constant(|c| -c.normal_stiffness), _mm512_mul_pd(overlap, root))), scale(u_n, eta));
    let old_length_sq = dot(old_delta, old_delta);
    let in_plane = sub(old_delta, scale(normal, dot(old_delta, normal)));
    let in_plane_length_sq = dot(in_plane, in_plane);
    // ×1 keeps the bits of a vector the scalar code leaves alone
    let one = _mm512_set1_pd(1.0);
    let rotated = _mm512_cmp_pd_mask::<_CMP_GT_OQ>(in_plane_length_sq, zero);
    let keep_length = _mm512_mask_blend_pd(rotated, one, _mm512_sqrt_pd(_mm512_div_pd(old_length_sq, in_plane_length_sq)));
    let delta = add(scale(in_plane, keep_length), scale(u_t, _mm512_set1_pd(dt)));
    let spring = _mm512_mul_pd(constant(|c| c.tangential_stiffness), root);
    let spring_force = scale(delta, negate(spring));
    let trial = sub(spring_force, scale(u_t, eta));
    let friction = constant(|c| c.friction);
    let f_n_sq = dot(f_n, f_n);
    let limit_sq = _mm512_mul_pd(_mm512_mul_pd(friction, friction), f_n_sq);
    let trial_sq = dot(trial, trial);
    let spring_sq = dot(spring_force, spring_force);

    // (T3.95) slip branch, computed in every lane and kept where the Coulomb limit is exceeded
    let thesis: __mmask8 = if shared {
        if c[0].slip_test == SlipTest::Thesis {
            0xff
        } else {
            0
        }
    } else {
        lane_indices.iter().fold(0, |mask, &l| mask | (((c[l].slip_test == SlipTest::Thesis) as u8) << l))
    };
    let exceeds = (thesis & _mm512_cmp_pd_mask::<_CMP_GT_OQ>(trial_sq, limit_sq)) | (!thesis & _mm512_cmp_pd_mask::<_CMP_GT_OQ>(spring_sq, limit_sq));
    // a group with no lane sliding (most of a settled bed's) keeps δ_t and the trial force,
    // as each lane would (a rescale by 1 keeps the bits)
    let (delta, tangential) = if exceeds == 0 { (delta, trial) } else { slip(exceeds, thesis, friction, f_n_sq, trial, trial_sq, delta, spring) };
    let force = add(f_n, tangential);
    let torque_a = cross(arm_a, tangential);
    let minus = V { x: negate(tangential.x), y: negate(tangential.y), z: negate(tangential.z) };
    let torque_b = cross(arm_b, minus);

    let elastic = if measure_energy { to_array(_mm512_mul_pd(_mm512_mul_pd(_mm512_set1_pd(0.4), _mm512_sqrt_pd(f_n_sq)), overlap)) } else { [0.0; 8] };
    let limit = _mm512_mul_pd(_mm512_set1_pd(MAX_OVERLAP_RATIO), _mm512_min_pd(ra, rb));
    let near_fault = _mm512_cmp_pd_mask::<_CMP_EQ_OQ>(distance, zero) | _mm512_cmp_pd_mask::<_CMP_GT_OQ>(overlap, limit);
    let done = !near_fault & touching & active;
    let apart = !(touching | active);
    // SAFETY (the transposes): this function runs where the processor has AVX-512 F
    let (history, force, torque_a, torque_b) = unsafe {
        (
            rows(delta.x, delta.y, delta.z, damping_ratio),
            rows(force.x, force.y, force.z, zero),
            rows(torque_a.x, torque_a.y, torque_a.z, zero),
            rows(torque_b.x, torque_b.y, torque_b.z, zero),
        )
    };
    let overlap = to_array(overlap);
    let mut result = [Lane::Scalar; 8];
    for l in 0..8 {
        if apart & (1 << l) != 0 {
            out[l].touching = false;
            result[l] = Lane::Apart;
        } else if done & (1 << l) != 0 {
            // SAFETY: l < 8 ≤ both lengths (checked above); the row stores of the AVX kernel
            // (a Touch is four f64, a PairForce nine f64 from its start, both repr(C))
            unsafe {
                _mm256_storeu_pd(touch.as_mut_ptr().add(l) as *mut f64, history[l]);
                let entry = out.as_mut_ptr().add(l) as *mut f64;
                _mm256_storeu_pd(entry, force[l]);
                _mm256_storeu_pd(entry.add(3), torque_a[l]);
                _mm256_maskstore_pd(entry.add(6), avx::xyz(), torque_b[l]);
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
/// tangential overlap and force (the AVX kernel's `slip`, eight wide).
#[allow(clippy::too_many_arguments)]
#[inline]
#[target_feature(enable = "avx512f")]
fn slip(exceeds: __mmask8, thesis: __mmask8, friction: __m512d, f_n_sq: __m512d, trial: V, trial_sq: __m512d, delta: V, spring: __m512d) -> (V, V) {
    let (zero, one) = (_mm512_setzero_pd(), _mm512_set1_pd(1.0));
    let limit = _mm512_mul_pd(friction, _mm512_sqrt_pd(f_n_sq));
    let trial_length = _mm512_sqrt_pd(trial_sq);
    let direction = select(_mm512_cmp_pd_mask::<_CMP_GT_OQ>(trial_length, zero), divide(trial, trial_length), V { x: zero, y: zero, z: zero });
    let sliding_force = scale(direction, limit);
    let delta_length = _mm512_sqrt_pd(dot(delta, delta));
    let spring_length = _mm512_mul_pd(spring, delta_length);
    let capped = _mm512_cmp_pd_mask::<_CMP_GT_OQ>(spring, zero)
        & _mm512_cmp_pd_mask::<_CMP_GT_OQ>(delta_length, zero)
        & _mm512_cmp_pd_mask::<_CMP_GT_OQ>(spring_length, limit);
    let rescaled = exceeds & thesis & capped;
    let rescale = _mm512_mask_blend_pd(rescaled, one, _mm512_div_pd(limit, spring_length));
    // OpenFOAM's test resets δ_t on slip (to +0, which a product with 0 would not give)
    let reset = !thesis & exceeds;
    let delta = select(reset, V { x: zero, y: zero, z: zero }, scale(delta, rescale));
    let tangential = select(exceeds, sliding_force, trial);
    (delta, tangential)
}
