/* Whether the pair style and the wall fixes take their AVX2 paths: chosen once per process, at
 * run time (the plugin is built for portable x86-64), when the CPU has AVX2 and the environment
 * does not set DASHPOT_LMP_SIMD=0. Every AVX2 path computes the same bits as its scalar one
 * (the same operations in the same order, no fused multiply-add): DASHPOT_LMP_SIMD=0 is there
 * to compare them, and for a CPU whose AVX2 one would rather not use. */
#ifndef DASHPOT_SIMD_H
#define DASHPOT_SIMD_H

#include <cstdlib>
#include <cstring>

namespace dashpot_lmp {

/* DASHPOT_LMP_SIMD is not "0". */
inline bool simd_allowed()
{
    static const bool allowed = [] {
        const char *s = std::getenv("DASHPOT_LMP_SIMD");
        return !(s && std::strcmp(s, "0") == 0);
    }();
    return allowed;
}

/* The AVX2 paths are on: the CPU has AVX2 and DASHPOT_LMP_SIMD allows them. */
inline bool simd_avx2()
{
#if defined(__x86_64__) || defined(__i386__)
    static const bool on = [] {
        __builtin_cpu_init();    // harmless if done: the CPU model may not be read yet in a plugin
        return simd_allowed() && __builtin_cpu_supports("avx2");
    }();
    return on;
#else
    return false;
#endif
}

}    // namespace dashpot_lmp

#endif
