/* The contact engine's forces and torques in AVX2: see dashpot_simd_torq.h. Only the functions
 * below are compiled for AVX2 (a target attribute on each, after every header), so nothing the
 * rest of the plugin links can carry an AVX2 instruction onto a CPU without it. */
#include "dashpot_simd_torq.h"

#if defined(__x86_64__)
#include <immintrin.h>

namespace dashpot_lmp {

namespace {

#define DASHPOT_AVX2 __attribute__((target("avx2")))

/* (v_y, v_z, v_x, v_4) */
DASHPOT_AVX2 inline __m256d yzx(__m256d v)
{
    return _mm256_permute4x64_pd(v, _MM_SHUFFLE(3, 0, 2, 1));
}

/* n x v as the scalar loop computes it, component by component: (n_y v_z - n_z v_y, n_z v_x -
 * n_x v_z, n_x v_y - n_y v_x), each product rounded, then the difference: u = n v.yzx - n.yzx v
 * holds (z, x, y) of it, and u.yzx is the cross product. */
DASHPOT_AVX2 inline __m256d cross(__m256d n, __m256d v)
{
    return yzx(_mm256_sub_pd(_mm256_mul_pd(n, yzx(v)), _mm256_mul_pd(yzx(n), v)));
}

/* row[3i .. 3i+2] += v's lanes 0..2 (lane 2 in hi's low lane), the scalar += of each component,
 * in four instructions: the additions take the row's doubles as their memory operand, and every
 * access is addressed from the array and the index (GCC would rather load the doubles first, to
 * keep v in its register, and form each row's address apart). */
DASHPOT_AVX2 inline void add3(double *row, long i, __m256d v, __m128d hi)
{
    __m128d t;
    asm volatile(
        "vaddpd (%[r],%[i],8), %x[v], %[t]\n\t"
        "vmovupd %[t], (%[r],%[i],8)\n\t"
        "vaddsd 16(%[r],%[i],8), %[h], %[t]\n\t"
        "vmovsd %[t], 16(%[r],%[i],8)"
        : [t] "=&x"(t)
        : [r] "r"(row), [i] "r"(3 * i), [v] "x"(v), [h] "x"(hi)
        : "memory");
}

/* p[0..2] = v's lanes 0..2 */
DASHPOT_AVX2 inline void put3(double *p, __m256d v, __m128d hi)
{
    _mm_storeu_pd(p, _mm256_castpd256_pd128(v));
    _mm_store_sd(p + 2, hi);
}

/* torques_of (dashpot_engine.cpp) a contact per register: F = fn n + F_t; c = n x F_t; the
 * rolling moment reff (n x F_roll) and the twisting one 0 + M n (the scalar loop's m starts at
 * 0.0: the same signed zeros); ta = m - arm_a c, tb = -m - arm_b c. The fourth lane carries
 * whatever follows each 3-vector and is never stored. */
template <bool ROLL, bool TWST, bool HALF, bool DIRECT>
DASHPOT_AVX2 void torques_of(ContactEngine::Chunk &c, int lo, int m, const ApplyTarget *direct)
{
    // each column at its constant offset from the chunk's double or int base (Chunk's
    // DoubleColumn, IntColumn): two registers for them all
    using Ch = ContactEngine::Chunk;
    const double *dbase = c.dstore.data();
    const int *ibase = c.istore.data();
    auto col = [dbase](int column) { return dbase + column * ContactEngine::CHUNK; };
    // newton's rule as one unsigned comparison: an atom takes its share when its index is below
    // `owned` (every atom with newton on, the local ones without); a wall's b < 0 never
    double *f = DIRECT ? direct->f : nullptr, *torque = DIRECT ? direct->torque : nullptr;
    const unsigned owned = !DIRECT ? 0u : direct->newton ? ~0u >> 1 : (unsigned) direct->nlocal;
    const __m256d sign = _mm256_set1_pd(-0.0);
    for (long k = lo; k < lo + m; k++) {
        const __m256d n = _mm256_loadu_pd(col(Ch::NORM) + 3 * k), ft = _mm256_loadu_pd(col(Ch::FT) + 3 * k);
        const __m256d F = _mm256_add_pd(_mm256_mul_pd(_mm256_broadcast_sd(col(Ch::FN) + k), n), ft);
        const __m256d cr = cross(n, ft);
        __m256d mo = _mm256_setzero_pd();
        if (ROLL)
            mo = _mm256_mul_pd(_mm256_broadcast_sd(col(Ch::RAD) + k), cross(n, _mm256_loadu_pd(c.froll + 3 * k)));
        if (TWST) mo = _mm256_add_pd(mo, _mm256_mul_pd(_mm256_broadcast_sd(c.mtwist + k), n));
        const double ra = col(Ch::RA)[k], rb = col(Ch::RB)[k], half_delta = HALF ? 0.5 * col(Ch::DELTA)[k] : 0.0;
        const double arm_a = HALF ? ra - half_delta : ra, arm_b = HALF ? rb - half_delta : rb;
        const __m256d ta = _mm256_sub_pd(mo, _mm256_mul_pd(_mm256_set1_pd(arm_a), cr));
        const __m256d tb = _mm256_sub_pd(_mm256_xor_pd(mo, sign), _mm256_mul_pd(_mm256_set1_pd(arm_b), cr));
        const __m128d Fz = _mm256_extractf128_pd(F, 1), taz = _mm256_extractf128_pd(ta, 1),
                      tbz = _mm256_extractf128_pd(tb, 1);
        if (!DIRECT) {
            put3(c.force + 3 * k, F, Fz);
            put3(c.ta + 3 * k, ta, taz);
            put3(c.tb + 3 * k, tb, tbz);
            continue;
        }
        const long a = ibase[Ch::A * ContactEngine::CHUNK + k], b = ibase[Ch::B * ContactEngine::CHUNK + k];
        if ((unsigned long) a < owned) {
            add3(f, a, F, Fz);
            add3(torque, a, ta, taz);
        }
        if ((unsigned long) b < owned) {
            // f_b - F as f_b + (-F): the same bits (IEEE subtraction is the addition of the
            // negated operand), with the row as the addition's memory operand
            const __m256d mF = _mm256_xor_pd(F, sign);
            add3(f, b, mF, _mm256_extractf128_pd(mF, 1));
            add3(torque, b, tb, tbz);
        }
    }
}

/* The kernel for torques_dispatch: one instantiation per combination of the flags. */
struct Avx2Torques {
    template <bool ROLL, bool TWST, bool HALF, bool DIRECT>
    static void run(ContactEngine::Chunk &c, int lo, int m, const ApplyTarget *direct)
    {
        torques_of<ROLL, TWST, HALF, DIRECT>(c, lo, m, direct);
    }
};

#undef DASHPOT_AVX2

}    // namespace

void torques_avx2(ContactEngine::Chunk &c, int lo, int m, bool roll, bool twst, bool half,
                  const ApplyTarget *direct)
{
    const bool flags[4] = {roll, twst, half, direct != nullptr};
    torques_dispatch<Avx2Torques>(c, lo, m, direct, flags);
}

}    // namespace dashpot_lmp

#else

namespace dashpot_lmp {

void torques_avx2(ContactEngine::Chunk &, int, int, bool, bool, bool, const ApplyTarget *) {}

}    // namespace dashpot_lmp

#endif
