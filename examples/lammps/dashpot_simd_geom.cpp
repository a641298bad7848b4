/* The AVX2 walk of pair_style dashpot's slots and staging of its contacts (see
 * dashpot_simd_geom.h). Every expression is the scalar code's (pair_dashpot_compute.cpp's walk
 * and geometry, dashpot_engine.h's stage_run_to), in the same order, four pairs per lane set. */
#include "dashpot_simd_geom.h"

#include "dashpot_engine.h"
#include "dashpot_simd.h"

#include <cmath>
#include <cstring>
#include <immintrin.h>


namespace dashpot_lmp {
namespace simd_geom {

bool enabled()
{
    return simd_avx2();
}

namespace {

/* The byte shuffles that pack the lanes set in a 4-bit mask of four 32-bit lanes to the front. */
struct PackTable {
    alignas(16) unsigned char shuf[16][16];
    constexpr PackTable() : shuf()
    {
        for (int m = 0; m < 16; m++) {
            int o = 0;
            for (int l = 0; l < 4; l++)
                if (m >> l & 1) {
                    for (int b = 0; b < 4; b++) shuf[m][4 * o + b] = (unsigned char) (4 * l + b);
                    o++;
                }
            for (; o < 4; o++)
                for (int b = 0; b < 4; b++) shuf[m][4 * o + b] = 0x80;
        }
    }
};
constexpr PackTable pack_table;

#define DASHPOT_AVX2 __attribute__((target("avx2")))

/* x, y, z of the atoms idx[0..3] from an array of 3 per atom: two loads a row (x, y together)
 * and a transpose, rather than gathers (slower here than the scalar loads they replace) */
DASHPOT_AVX2 inline void rows3(const double *p, const int *idx, __m256d &X, __m256d &Y, __m256d &Z)
{
    const double *p0 = p + 3 * (ptrdiff_t) idx[0], *p1 = p + 3 * (ptrdiff_t) idx[1];
    const double *p2 = p + 3 * (ptrdiff_t) idx[2], *p3 = p + 3 * (ptrdiff_t) idx[3];
    const __m256d t02 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p0)), _mm_loadu_pd(p2), 1);
    const __m256d t13 = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p1)), _mm_loadu_pd(p3), 1);
    X = _mm256_unpacklo_pd(t02, t13);
    Y = _mm256_unpackhi_pd(t02, t13);
    const __m128d z01 = _mm_loadh_pd(_mm_load_sd(p0 + 2), p1 + 2), z23 = _mm_loadh_pd(_mm_load_sd(p2 + 2), p3 + 2);
    Z = _mm256_insertf128_pd(_mm256_castpd128_pd256(z01), z23, 1);
}

/* v[idx[0..3]] */
DASHPOT_AVX2 inline __m256d lanes(const double *v, const int *idx)
{
    return _mm256_setr_pd(v[idx[0]], v[idx[1]], v[idx[2]], v[idx[3]]);
}

/* stores the lanes of X, Y, Z as 4 rows of 3 (x0 y0 z0 x1 y1 z1 ...) at p */
DASHPOT_AVX2 inline void store_rows3(double *p, __m256d X, __m256d Y, __m256d Z)
{
    const __m256d a = _mm256_unpacklo_pd(X, Y);    // x0 y0 | x2 y2
    const __m256d b = _mm256_unpackhi_pd(X, Y);    // x1 y1 | x3 y3
    const __m256d c = _mm256_unpacklo_pd(Z, b);    // z0 x1 | z2 x3
    const __m256d e = _mm256_unpackhi_pd(b, Z);    // y1 z1 | y3 z3
    _mm256_storeu_pd(p, _mm256_permute2f128_pd(a, c, 0x20));
    _mm256_storeu_pd(p + 4, _mm256_permute2f128_pd(e, a, 0x30));
    _mm256_storeu_pd(p + 8, _mm256_permute2f128_pd(c, e, 0x31));
}

}    // namespace

namespace {

/* walk() with history records to check (HIST) or without, with an adhesive law (ADH) */
template <bool HIST, bool ADH>
DASHPOT_AVX2 inline int walk_of(const Slots &s, int k0, int k1, int *out, int *ended, int &nended)
{
    const int *pairs = s.pairs;
    const double *x0 = s.x0, *radius = s.radius, *reach = s.reach;
    const unsigned char *touched = s.touched;
    int *o = out, *z = ended + nended;
    int k = k0;
    __m128i ks = _mm_add_epi32(_mm_set1_epi32(k0), _mm_setr_epi32(0, 1, 2, 3));
    for (; k + 4 <= k1; k += 4) {
        const int *p = pairs + 2 * k;
        const int I[4] = {p[0], p[2], p[4], p[6]}, J[4] = {p[1], p[3], p[5], p[7]};
        __m256d xi, yi, zi, xj, yj, zj;
        rows3(x0, I, xi, yi, zi);
        rows3(x0, J, xj, yj, zj);
        const __m256d dx = _mm256_sub_pd(xi, xj), dy = _mm256_sub_pd(yi, yj), dz = _mm256_sub_pd(zi, zj);
        const __m256d rsq =
            _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz));
        const __m256d radsum = _mm256_add_pd(lanes(radius, I), lanes(radius, J));
        int touch = _mm256_movemask_pd(_mm256_cmp_pd(rsq, _mm256_mul_pd(radsum, radsum), _CMP_LT_OQ));
        int tm = 0;
        if (HIST) {
            int t4;
            std::memcpy(&t4, touched + k, 4);
            tm = _mm_movemask_epi8(_mm_cmpgt_epi8(_mm_cvtsi32_si128(t4), _mm_setzero_si128())) & 0xF;
        }
        if (ADH && (tm & ~touch)) {
            // a touched record whose pair is apart: in contact while within its law's reach
            alignas(32) double rs[4], rad[4];
            _mm256_store_pd(rs, rsq);
            _mm256_store_pd(rad, radsum);
            for (int l = 0; l < 4; l++)
                if ((tm & ~touch) >> l & 1 && std::sqrt(rs[l]) - rad[l] <= reach[k + l]) touch |= 1 << l;
        }
        // the touching slots packed to the front
        _mm_storeu_si128((__m128i *) o, _mm_shuffle_epi8(ks, _mm_load_si128((const __m128i *) pack_table.shuf[touch])));
        o += __builtin_popcount(touch);
        ks = _mm_add_epi32(ks, _mm_set1_epi32(4));
        // a record touched whose pair no longer touches: rare
        if (HIST)
            if (const int gone = tm & ~touch)
                for (int l = 0; l < 4; l++)
                    if (gone >> l & 1) *z++ = k + l;
    }
    for (; k < k1; k++) {
        const int i = pairs[2 * k], j = pairs[2 * k + 1];
        const double *xi = x0 + 3 * (ptrdiff_t) i, *xj = x0 + 3 * (ptrdiff_t) j;
        const double dx = xi[0] - xj[0], dy = xi[1] - xj[1], dz = xi[2] - xj[2];
        const double rsq = dx * dx + dy * dy + dz * dz;
        const double radsum = radius[i] + radius[j];
        int touch = rsq < radsum * radsum;
        if (ADH && touched[k] > touch) touch = std::sqrt(rsq) - radsum <= reach[k];
        *o = k;
        o += touch;
        if (HIST && touched[k] > touch) *z++ = k;
    }
    nended = (int) (z - ended);
    return (int) (o - out);
}

}    // namespace

DASHPOT_AVX2 int walk(const Slots &s, int k0, int k1, int *out, int *ended, int &nended)
{
    if (s.reach) return walk_of<true, true>(s, k0, k1, out, ended, nended);
    if (s.touched) return walk_of<true, false>(s, k0, k1, out, ended, nended);
    return walk_of<false, false>(s, k0, k1, out, ended, nended);
}

namespace {

/* stage() with a freeze group or without (FROZEN): each column stored as soon as it is known,
 * which keeps the lanes in the 16 registers */
template <bool FROZEN>
DASHPOT_AVX2 inline void stage_of(const Atoms &at, const int *kq, int m, int model, int *iv, double *dv, int k)
{
    using Chunk = ContactEngine::Chunk;
    constexpr int C = ContactEngine::CHUNK;
    for (int q = 0; q < m; q += 4, k += 4) {
        // the same bits from either side: oriented from the atom of the lower tag
        int A[4], B[4];
        for (int l = 0; l < 4; l++) {
            const int s = kq[q + l], i = at.pairs[2 * s], j = at.pairs[2 * s + 1];
            const bool swap = at.tag[j] < at.tag[i];
            A[l] = swap ? j : i;
            B[l] = swap ? i : j;
        }
        const __m128i va = _mm_loadu_si128((const __m128i *) A), vb = _mm_loadu_si128((const __m128i *) B);
        _mm_storeu_si128((__m128i *) (iv + Chunk::A * C + k), va);
        _mm_storeu_si128((__m128i *) (iv + Chunk::B * C + k), vb);
        _mm_storeu_si128((__m128i *) (iv + Chunk::SLOT * C + k), _mm_loadu_si128((const __m128i *) (kq + q)));
        _mm_storeu_si128((__m128i *) (iv + Chunk::MODEL * C + k), _mm_set1_epi32(model));
        const __m256d ra = lanes(at.radius, A), rb = lanes(at.radius, B);
        const __m256d radsum = _mm256_add_pd(ra, rb);
        _mm256_storeu_pd(dv + Chunk::RA * C + k, ra);
        _mm256_storeu_pd(dv + Chunk::RB * C + k, rb);
        _mm256_storeu_pd(dv + Chunk::RAD * C + k, _mm256_div_pd(_mm256_mul_pd(ra, rb), radsum));
        {
            const __m256d ma = lanes(at.rmass, A), mb = lanes(at.rmass, B);
            __m256d meff = _mm256_div_pd(_mm256_mul_pd(ma, mb), _mm256_add_pd(ma, mb));
            if (FROZEN) {
                // all ones in the lanes whose body is not frozen (as the scalar code: a frozen a
                // gives mb, then a frozen b gives ma)
                const int f = at.frozen, *mask = at.mask;
                const __m256d fa = _mm256_castsi256_pd(_mm256_setr_epi64x(
                    -!(mask[A[0]] & f), -!(mask[A[1]] & f), -!(mask[A[2]] & f), -!(mask[A[3]] & f)));
                const __m256d fb = _mm256_castsi256_pd(_mm256_setr_epi64x(
                    -!(mask[B[0]] & f), -!(mask[B[1]] & f), -!(mask[B[2]] & f), -!(mask[B[3]] & f)));
                meff = _mm256_blendv_pd(mb, meff, fa);
                meff = _mm256_blendv_pd(ma, meff, fb);
            }
            _mm256_storeu_pd(dv + Chunk::MASS * C + k, meff);
        }
        __m256d nx, ny, nz;
        {
            __m256d xa, ya, za, xb, yb, zb;
            rows3(at.x0, A, xa, ya, za);
            rows3(at.x0, B, xb, yb, zb);
            const __m256d dx = _mm256_sub_pd(xa, xb), dy = _mm256_sub_pd(ya, yb), dz = _mm256_sub_pd(za, zb);
            const __m256d rsq =
                _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz));
            const __m256d r = _mm256_sqrt_pd(rsq);
            const __m256d rinv = _mm256_div_pd(_mm256_set1_pd(1.0), r);
            _mm256_storeu_pd(dv + Chunk::DELTA * C + k, _mm256_sub_pd(radsum, r));
            nx = _mm256_mul_pd(dx, rinv);
            ny = _mm256_mul_pd(dy, rinv);
            nz = _mm256_mul_pd(dz, rinv);
            store_rows3(dv + Chunk::NORM * C + 3 * k, nx, ny, nz);
        }
        __m256d dvx, dvy, dvz, vn;
        {
            __m256d vxa, vya, vza, vxb, vyb, vzb;
            rows3(at.v0, A, vxa, vya, vza);
            rows3(at.v0, B, vxb, vyb, vzb);
            dvx = _mm256_sub_pd(vxa, vxb);
            dvy = _mm256_sub_pd(vya, vyb);
            dvz = _mm256_sub_pd(vza, vzb);
            vn = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dvx, nx), _mm256_mul_pd(dvy, ny)), _mm256_mul_pd(dvz, nz));
            _mm256_storeu_pd(dv + Chunk::RATE * C + k, _mm256_xor_pd(vn, _mm256_set1_pd(-0.0)));
        }
        __m256d wxa, wya, wza, wxb, wyb, wzb;
        rows3(at.w0, A, wxa, wya, wza);
        rows3(at.w0, B, wxb, wyb, wzb);
        const __m256d wx = _mm256_add_pd(_mm256_mul_pd(ra, wxa), _mm256_mul_pd(rb, wxb));
        const __m256d wy = _mm256_add_pd(_mm256_mul_pd(ra, wya), _mm256_mul_pd(rb, wyb));
        const __m256d wz = _mm256_add_pd(_mm256_mul_pd(ra, wza), _mm256_mul_pd(rb, wzb));
        const __m256d cvx = _mm256_sub_pd(_mm256_sub_pd(dvx, _mm256_mul_pd(vn, nx)),
                                          _mm256_sub_pd(_mm256_mul_pd(wy, nz), _mm256_mul_pd(wz, ny)));
        const __m256d cvy = _mm256_sub_pd(_mm256_sub_pd(dvy, _mm256_mul_pd(vn, ny)),
                                          _mm256_sub_pd(_mm256_mul_pd(wz, nx), _mm256_mul_pd(wx, nz)));
        const __m256d cvz = _mm256_sub_pd(_mm256_sub_pd(dvz, _mm256_mul_pd(vn, nz)),
                                          _mm256_sub_pd(_mm256_mul_pd(wx, ny), _mm256_mul_pd(wy, nx)));
        store_rows3(dv + Chunk::VEL * C + 3 * k, cvx, cvy, cvz);
    }
}

}    // namespace

DASHPOT_AVX2 void stage(const Atoms &at, const int *kq, int m, int model, int *iv, double *dv, int k)
{
    if (at.frozen)
        stage_of<true>(at, kq, m, model, iv, dv, k);
    else
        stage_of<false>(at, kq, m, model, iv, dv, k);
}

}    // namespace simd_geom
}    // namespace dashpot_lmp
