/* pair_style dashpot's walk of its history slots and staging of the touching pairs, four pairs
 * at a time in AVX2. The plugin is built for portable x86-64: these functions are compiled for
 * AVX2 alone (never FMA: every result is rounded as the scalar code rounds it, operation for
 * operation; square roots and divisions are correctly rounded in both), and called only when
 * the CPU has AVX2. The results are the same bits as the scalar walk and staging
 * (pair_dashpot_compute.cpp); DASHPOT_LMP_SIMD=0 in the environment forces the scalar code.
 * The atoms' rows are loaded two loads a row (x and y together, then z) and transposed into
 * lanes: AVX2's gathers would execute fewer instructions but, on the Xeons measured, take
 * longer than the scalar code, the staging then waiting on them. */
#ifndef DASHPOT_SIMD_GEOM_H
#define DASHPOT_SIMD_GEOM_H

namespace dashpot_lmp {
namespace simd_geom {

/* Whether the AVX2 walk and staging run: the CPU has AVX2 and DASHPOT_LMP_SIMD is not 0 (read
 * once per process: simd_avx2() of dashpot_simd.h, the switch every AVX2 path shares). */
bool enabled();

/* A list's slots as the walk reads them: pairs[2k], pairs[2k + 1] the atoms i, j of slot k, x0
 * the positions (3 per atom, contiguous), radius the radii; with history, each slot's record's
 * `touched` flag (0 or 1), and with an adhesive law the reach of its last call. */
struct Slots {
    const int *pairs;
    const double *x0, *radius;
    const unsigned char *touched;    // null: no history
    const double *reach;             // null: no adhesive law (needs `touched`)
};

/* Walks the slots k0 <= k < k1: writes the slots of the touching pairs to `out` in slot order
 * and returns their number (`out` has room for k1 - k0 + 3 values). A pair touches as in the
 * scalar walk: |x_i - x_j|^2 < (r_i + r_j)^2, or with an adhesive law, a touched record and
 * |x_i - x_j| - (r_i + r_j) <= its reach. With history, also appends the slots whose record was
 * touched and whose pair no longer touches to `ended` (nended: their number). */
int walk(const Slots &s, int k0, int k1, int *out, int *ended, int &nended);

/* The atoms' arrays the staging reads (LAMMPS's, contiguous; tagint is int). */
struct Atoms {
    const int *pairs;    // 2 per slot: the slot's atoms i, j
    const double *x0, *v0, *w0, *radius, *rmass;
    const int *tag, *mask;
    int frozen;    // the freeze group's bit (0: none): a frozen body's partner takes the whole mass
};

/* Stages the m touching pairs of slots kq[0..m) (m a multiple of 4) at rows k, k + 1, ... of a
 * chunk whose int columns start at iv and double columns at dv (ContactEngine::Chunk's fixed
 * layout, CHUNK rows each), with bound model `model`: the same columns, the same bits, as the
 * scalar staging (oriented from the atom of the lower tag). */
void stage(const Atoms &at, const int *kq, int m, int model, int *iv, double *dv, int k);

}    // namespace simd_geom
}    // namespace dashpot_lmp

#endif
