/* The contact engine's forces and torques in AVX2 (dashpot_simd_torq.cpp): one contact's three
 * components in the lanes of one register, with the same operations in the same order as the
 * scalar loop of dashpot_engine.cpp (no fused multiply-add), hence the same bits. Called only
 * when simd_avx2() (dashpot_simd.h) holds. */
#ifndef DASHPOT_SIMD_TORQ_H
#define DASHPOT_SIMD_TORQ_H

#include "dashpot_engine.h"

namespace dashpot_lmp {

/* Kernel::run<ROLL, TWST, HALF, DIRECT>(c, lo, m, direct) with the four flags (rolling,
 * twisting, granular's contact-point arm, straight to the atoms' arrays) as its template
 * arguments: one loop per combination, with no test inside but newton's rule. */
template <class Kernel, bool... B>
inline void torques_dispatch(ContactEngine::Chunk &c, int lo, int m, const ApplyTarget *direct, const bool *flags)
{
    if constexpr (sizeof...(B) == 4)
        Kernel::template run<B...>(c, lo, m, direct);
    else if (flags[sizeof...(B)])
        torques_dispatch<Kernel, B..., true>(c, lo, m, direct, flags);
    else
        torques_dispatch<Kernel, B..., false>(c, lo, m, direct, flags);
}

/* As ContactEngine::torques on contacts lo .. lo+m-1 of chunk c: rolling (roll), twisting
 * (twst), granular's contact-point arm (half); into the chunk's force, ta, tb columns or added to
 * `direct`'s arrays. The chunk's columns must be padded by one double past their last (reserve()
 * pads them): each 3-vector is read with a 4-wide load. */
void torques_avx2(ContactEngine::Chunk &c, int lo, int m, bool roll, bool twst, bool half,
                  const ApplyTarget *direct);

}    // namespace dashpot_lmp

#endif
