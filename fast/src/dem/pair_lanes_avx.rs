//! [`super::pair_lanes`]'s four pairs written out in AVX instructions: the same IEEE
//! operations in the same order, lane by lane (nothing fused, divisions and square roots as
//! such), so each lane keeps the bits of the scalar contact; the unit test in
//! [`super::pair_lanes`] holds all three to the bit.
//!
//! Written with the compiler left to vectorise the lane arrays, the kernel came out as 1900
//! instructions, most of them spills, shuffles and scalar square roots; the selects of the
//! slip branch (lane by lane `if`s there) are blends here, and every quantity stays in a
//! 256-bit register.

use std::arch::x86_64::*;

use spillage_model::closure::contact::SlipTest;
use spillage_model::particles::guards::MAX_OVERLAP_RATIO;
use spillage_model::particles::state::Vec3;

use super::arrays::ParticleArrays;
use super::neighbour_list::{PairEnergy, PairForce};
use super::pair_lanes::{FourPairs, Lane};

/// Four 3-vectors, one per lane.
#[derive(Clone, Copy)]
struct V {
    x: __m256d,
    y: __m256d,
    z: __m256d,
}

/// Lane l of `f(l)`, as one register.
#[inline]
#[target_feature(enable = "avx")]
fn lanes(f: impl Fn(usize) -> f64) -> __m256d {
    _mm256_set_pd(f(3), f(2), f(1), f(0))
}

#[inline]
#[target_feature(enable = "avx")]
fn gather(f: impl Fn(usize) -> Vec3) -> V {
    let v = [f(0), f(1), f(2), f(3)];
    V { x: _mm256_set_pd(v[3].x, v[2].x, v[1].x, v[0].x), y: _mm256_set_pd(v[3].y, v[2].y, v[1].y, v[0].y), z: _mm256_set_pd(v[3].z, v[2].z, v[1].z, v[0].z) }
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

/// The four lanes' vectors.
#[inline]
#[target_feature(enable = "avx")]
fn unpack(v: V) -> [Vec3; 4] {
    let (x, y, z) = (to_array(v.x), to_array(v.y), to_array(v.z));
    [0, 1, 2, 3].map(|l| Vec3::new(x[l], y[l], z[l]))
}

#[inline]
#[target_feature(enable = "avx")]
fn to_array(v: __m256d) -> [f64; 4] {
    let mut a = [0.0; 4];
    // SAFETY: `a` holds four f64 (unaligned store).
    unsafe { _mm256_storeu_pd(a.as_mut_ptr(), v) };
    a
}

/// [`super::pair_lanes::four_pairs`] in AVX instructions (the caller checked the processor has
/// them).
#[target_feature(enable = "avx")]
pub fn four_pairs_avx(group: FourPairs, arrays: &ParticleArrays, dt: f64, measure_energy: bool) -> [Lane; 4] {
    let FourPairs { pairs, constants, touch, energy, out } = group;
    let (a, b) = ([0, 1, 2, 3].map(|l| pairs[l].a as usize), [0, 1, 2, 3].map(|l| pairs[l].b as usize));
    let c = [0, 1, 2, 3].map(|l| &constants[pairs[l].constants as usize]);
    let zero = _mm256_setzero_pd();
    let ra = lanes(|l| arrays.radius[a[l]]);
    let rb = lanes(|l| arrays.radius[b[l]]);
    let offset = sub(gather(|l| arrays.position[b[l]]), gather(|l| arrays.position[a[l]]));
    let distance = _mm256_sqrt_pd(dot(offset, offset));
    let reach = _mm256_add_pd(ra, rb);
    let overlap = _mm256_sub_pd(reach, distance);

    let normal = divide(offset, distance);
    let arm_a = scale(normal, ra);
    let arm_b = scale(normal, negate(rb));
    let v_rel = sub(
        add(gather(|l| arrays.velocity[a[l]]), cross(gather(|l| arrays.spin[a[l]]), arm_a)),
        add(gather(|l| arrays.velocity[b[l]]), cross(gather(|l| arrays.spin[b[l]]), arm_b)),
    );

    // hertz_mindlin_force, lane by lane
    let approach_speed = dot(v_rel, normal);
    let u_n = scale(normal, approach_speed);
    let u_t = sub(v_rel, u_n);
    // max(δ, 0) as f64::max takes it for every δ a kept lane can have (δ > 0)
    let root = _mm256_sqrt_pd(_mm256_max_pd(overlap, zero));
    let eta = _mm256_mul_pd(lanes(|l| touch[l].damping_ratio() * c[l].damping_scale), _mm256_sqrt_pd(root));
    let f_n = sub(scale(normal, _mm256_mul_pd(lanes(|l| -c[l].normal_stiffness), _mm256_mul_pd(overlap, root))), scale(u_n, eta));
    let old_delta = gather(|l| touch[l].tangential_overlap);
    let old_length_sq = dot(old_delta, old_delta);
    let in_plane = sub(old_delta, scale(normal, dot(old_delta, normal)));
    let in_plane_length_sq = dot(in_plane, in_plane);
    // ×1 keeps the bits of a vector the scalar code leaves alone
    let one = _mm256_set1_pd(1.0);
    let rotated = _mm256_cmp_pd::<_CMP_GT_OQ>(in_plane_length_sq, zero);
    let keep_length = _mm256_blendv_pd(one, _mm256_sqrt_pd(_mm256_div_pd(old_length_sq, in_plane_length_sq)), rotated);
    let delta = add(scale(in_plane, keep_length), scale(u_t, _mm256_set1_pd(dt)));
    let spring = _mm256_mul_pd(lanes(|l| c[l].tangential_stiffness), root);
    let spring_force = scale(delta, negate(spring));
    let trial = sub(spring_force, scale(u_t, eta));
    let friction = lanes(|l| c[l].friction);
    let f_n_sq = dot(f_n, f_n);
    let limit_sq = _mm256_mul_pd(_mm256_mul_pd(friction, friction), f_n_sq);
    let trial_sq = dot(trial, trial);
    let spring_sq = dot(spring_force, spring_force);

    // (T3.95) slip branch, computed in every lane and kept where the Coulomb limit is exceeded
    let thesis = lanes(|l| if c[l].slip_test == SlipTest::Thesis { f64::from_bits(u64::MAX) } else { 0.0 });
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
    let touching = _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(distance, reach));
    let (ra, rb, distance, overlap) = (to_array(ra), to_array(rb), to_array(distance), to_array(overlap));
    let (delta, force, torque_a, torque_b) = (unpack(delta), unpack(force), unpack(torque_a), unpack(torque_b));
    let mut result = [Lane::Scalar; 4];
    for l in 0..4 {
        if touching & (1 << l) == 0 {
            if !touch[l].active() {
                out[l].touching = false;
                result[l] = Lane::Apart;
            }
            continue;
        }
        let near_fault = distance[l] == 0.0 || overlap[l] > MAX_OVERLAP_RATIO * ra[l].min(rb[l]);
        if !touch[l].active() || near_fault {
            continue;
        }
        touch[l].tangential_overlap = delta[l];
        out[l] = PairForce { touching: true, force: force[l], torque_a: torque_a[l], torque_b: torque_b[l] };
        if measure_energy {
            energy[l] = PairEnergy { overlap: overlap[l], elastic: elastic[l], placed: 0.0 };
        }
        result[l] = Lane::Done;
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
