// The E-step of vmf_estep.cpp in AVX2 + FMA intrinsics, chosen at run time where the CPU has
// them. Same arithmetic as the portable kernel (double log-terms, Cephes float exp/log), written
// out so that the compiler keeps the float <-> double conversions to one instruction each and the
// per-lobe constants in registers.
#include "methods/vmf/vmf_internal.h"

#if defined(__x86_64__) && defined(__GNUC__)

#pragma GCC target("avx2,fma")
#include <immintrin.h>

namespace ndfmip::vmf {
namespace {

// Eight float lanes as two groups of four doubles.
inline __m256d lowHalf(__m256 v) {
    return _mm256_cvtps_pd(_mm256_castps256_ps128(v));
}
inline __m256d highHalf(__m256 v) {
    return _mm256_cvtps_pd(_mm256_extractf128_ps(v, 1));
}
inline __m256 join(__m256d low, __m256d high) {
    return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm256_cvtpd_ps(low)), _mm256_cvtpd_ps(high),
                                1);
}

// e^t for t <= 0 (expNonPositive of vmf_estep.cpp).
inline __m256 expNonPositive(__m256 t) {
    const __m256 lowest = _mm256_set1_ps(-87.33f);
    __m256 underflow = _mm256_cmp_ps(t, lowest, _CMP_LT_OQ);
    t = _mm256_max_ps(t, lowest);
    const __m256 shifter = _mm256_set1_ps(12582912.f);
    __m256 k = _mm256_fmadd_ps(t, _mm256_set1_ps(1.44269504088896341f), shifter);
    __m256 n = _mm256_sub_ps(k, shifter);
    __m256 r = _mm256_fnmadd_ps(n, _mm256_set1_ps(0.693359375f), t);
    r = _mm256_fmadd_ps(n, _mm256_set1_ps(2.12194440e-4f), r);
    __m256 p = _mm256_set1_ps(1.9875691500e-4f);
    p = _mm256_fmadd_ps(p, r, _mm256_set1_ps(1.3981999507e-3f));
    p = _mm256_fmadd_ps(p, r, _mm256_set1_ps(8.3334519073e-3f));
    p = _mm256_fmadd_ps(p, r, _mm256_set1_ps(4.1665795894e-2f));
    p = _mm256_fmadd_ps(p, r, _mm256_set1_ps(1.6666665459e-1f));
    p = _mm256_fmadd_ps(p, r, _mm256_set1_ps(5.0000001201e-1f));
    __m256 y = _mm256_fmadd_ps(p, _mm256_mul_ps(r, r), _mm256_add_ps(r, _mm256_set1_ps(1.f)));
    __m256i scale =
        _mm256_slli_epi32(_mm256_add_epi32(_mm256_castps_si256(k), _mm256_set1_epi32(127)), 23);
    return _mm256_andnot_ps(underflow, _mm256_mul_ps(y, _mm256_castsi256_ps(scale)));
}

// log(s) for s >= 1 (logAtLeastOne of vmf_estep.cpp).
inline __m256 logAtLeastOne(__m256 s) {
    __m256i bits = _mm256_castps_si256(s);
    __m256i e = _mm256_sub_epi32(_mm256_srli_epi32(bits, 23), _mm256_set1_epi32(126));
    __m256 m = _mm256_castsi256_ps(_mm256_or_si256(
        _mm256_and_si256(bits, _mm256_set1_epi32(0x7fffff)), _mm256_set1_epi32(0x3f000000)));
    __m256 small = _mm256_cmp_ps(m, _mm256_set1_ps(0.707106781186547524f), _CMP_LT_OQ);
    e = _mm256_add_epi32(e, _mm256_castps_si256(small)); // -1 where small
    __m256 x = _mm256_sub_ps(_mm256_add_ps(m, _mm256_and_ps(small, m)), _mm256_set1_ps(1.f));
    __m256 z = _mm256_mul_ps(x, x);
    __m256 y = _mm256_set1_ps(7.0376836292e-2f);
    y = _mm256_fmadd_ps(y, x, _mm256_set1_ps(-1.1514610310e-1f));
    y = _mm256_fmadd_ps(y, x, _mm256_set1_ps(1.1676998740e-1f));
    y = _mm256_fmadd_ps(y, x, _mm256_set1_ps(-1.2420140846e-1f));
    y = _mm256_fmadd_ps(y, x, _mm256_set1_ps(1.4249322787e-1f));
    y = _mm256_fmadd_ps(y, x, _mm256_set1_ps(-1.6668057665e-1f));
    y = _mm256_fmadd_ps(y, x, _mm256_set1_ps(2.0000714765e-1f));
    y = _mm256_fmadd_ps(y, x, _mm256_set1_ps(-2.4999993993e-1f));
    y = _mm256_fmadd_ps(y, x, _mm256_set1_ps(3.3333331174e-1f));
    y = _mm256_mul_ps(_mm256_mul_ps(y, x), z);
    __m256 fe = _mm256_cvtepi32_ps(e);
    y = _mm256_fnmadd_ps(fe, _mm256_set1_ps(2.12194440e-4f), y);
    y = _mm256_fnmadd_ps(_mm256_set1_ps(0.5f), z, y);
    return _mm256_fmadd_ps(fe, _mm256_set1_ps(0.693359375f), _mm256_add_ps(x, y));
}

double laneTotal(__m256 v) {
    alignas(32) float lane[8];
    _mm256_store_ps(lane, v);
    double t = 0;
    for (float l : lane) t += double(l);
    return t;
}

template <bool Weighted, int FixedJ>
void blocks(const float* px, const float* py, const float* pz, const float* pw, size_t begin,
            size_t end, const LobeTerms& lobes, Moments& out) {
    const int J = FixedJ > 0 ? FixedJ : lobes.count;
    if (J < 1 || J > kMaxVmfLobes) __builtin_unreachable();
    __m256d c[kMaxVmfLobes], kx[kMaxVmfLobes], ky[kMaxVmfLobes], kz[kMaxVmfLobes];
    __m256 mx[kMaxVmfLobes], my[kMaxVmfLobes], mz[kMaxVmfLobes];
    __m256 sumN[kMaxVmfLobes], sumX[kMaxVmfLobes], sumY[kMaxVmfLobes], sumZ[kMaxVmfLobes];
    for (int j = 0; j < J; ++j) {
        c[j] = _mm256_set1_pd(lobes.c[j]);
        kx[j] = _mm256_set1_pd(lobes.kx[j]);
        ky[j] = _mm256_set1_pd(lobes.ky[j]);
        kz[j] = _mm256_set1_pd(lobes.kz[j]);
        mx[j] = _mm256_set1_ps(lobes.mx[j]);
        my[j] = _mm256_set1_ps(lobes.my[j]);
        mz[j] = _mm256_set1_ps(lobes.mz[j]);
        sumN[j] = sumX[j] = sumY[j] = sumZ[j] = _mm256_setzero_ps();
    }
    __m256d sumLogLikelihood = _mm256_setzero_pd();
    __m256d sLow[kMaxVmfLobes], sHigh[kMaxVmfLobes];
    __m256 e[kMaxVmfLobes];

    for (size_t i = begin; i < end; i += 8) {
        __m256 nx = _mm256_loadu_ps(px + i), ny = _mm256_loadu_ps(py + i),
               nz = _mm256_loadu_ps(pz + i);
        __m256d xLow = lowHalf(nx), yLow = lowHalf(ny), zLow = lowHalf(nz);
        __m256d xHigh = highHalf(nx), yHigh = highHalf(ny), zHigh = highHalf(nz);
        for (int j = 0; j < J; ++j) {
            sLow[j] = _mm256_fmadd_pd(
                kz[j], zLow, _mm256_fmadd_pd(ky[j], yLow, _mm256_fmadd_pd(kx[j], xLow, c[j])));
            sHigh[j] = _mm256_fmadd_pd(
                kz[j], zHigh, _mm256_fmadd_pd(ky[j], yHigh, _mm256_fmadd_pd(kx[j], xHigh, c[j])));
        }
        __m256d topLow = sLow[0], topHigh = sHigh[0];
        for (int j = 1; j < J; ++j) {
            topLow = _mm256_max_pd(topLow, sLow[j]);
            topHigh = _mm256_max_pd(topHigh, sHigh[j]);
        }
        // A lobe below e^-87 for all eight normals (a sharp lobe far away) contributes exact
        // zeros: skip its exp and its moments.
        __m256 sum = _mm256_setzero_ps();
        unsigned negligible = 0;
        for (int j = 0; j < J; ++j) {
            __m256 t = join(_mm256_sub_pd(sLow[j], topLow), _mm256_sub_pd(sHigh[j], topHigh));
            if (_mm256_movemask_ps(_mm256_cmp_ps(t, _mm256_set1_ps(-87.33f), _CMP_LT_OQ)) == 0xff) {
                negligible |= 1u << j;
                e[j] = _mm256_setzero_ps();
                continue;
            }
            e[j] = expNonPositive(t);
            sum = _mm256_add_ps(sum, e[j]);
        }
        __m256 logSum = logAtLeastOne(sum);
        __m256d logDensityLow = _mm256_add_pd(topLow, lowHalf(logSum));
        __m256d logDensityHigh = _mm256_add_pd(topHigh, highHalf(logSum));
        __m256 scale = _mm256_div_ps(_mm256_set1_ps(1.f), sum);
        if constexpr (Weighted) {
            __m256 w = _mm256_loadu_ps(pw + i);
            scale = _mm256_mul_ps(scale, w);
            sumLogLikelihood = _mm256_fmadd_pd(logDensityLow, lowHalf(w), sumLogLikelihood);
            sumLogLikelihood = _mm256_fmadd_pd(logDensityHigh, highHalf(w), sumLogLikelihood);
        } else {
            sumLogLikelihood =
                _mm256_add_pd(sumLogLikelihood, _mm256_add_pd(logDensityLow, logDensityHigh));
        }
        for (int j = 0; j < J; ++j) {
            if (negligible & (1u << j)) continue;
            __m256 z = _mm256_mul_ps(e[j], scale);
            sumN[j] = _mm256_add_ps(sumN[j], z);
            sumX[j] = _mm256_fmadd_ps(z, _mm256_sub_ps(nx, mx[j]), sumX[j]);
            sumY[j] = _mm256_fmadd_ps(z, _mm256_sub_ps(ny, my[j]), sumY[j]);
            sumZ[j] = _mm256_fmadd_ps(z, _mm256_sub_ps(nz, mz[j]), sumZ[j]);
        }
    }

    for (int j = 0; j < J; ++j) {
        out.n[j] += laneTotal(sumN[j]);
        out.rx[j] += laneTotal(sumX[j]);
        out.ry[j] += laneTotal(sumY[j]);
        out.rz[j] += laneTotal(sumZ[j]);
    }
    alignas(32) double lane[4];
    _mm256_store_pd(lane, sumLogLikelihood);
    out.logLikelihood += (lane[0] + lane[1]) + (lane[2] + lane[3]);
}

template <bool Weighted>
void blocksAnyJ(const float* px, const float* py, const float* pz, const float* pw, size_t begin,
                size_t end, const LobeTerms& lobes, Moments& out) {
    switch (lobes.count) {
    case 1:
        return blocks<Weighted, 1>(px, py, pz, pw, begin, end, lobes, out);
    case 2:
        return blocks<Weighted, 2>(px, py, pz, pw, begin, end, lobes, out);
    case 3:
        return blocks<Weighted, 3>(px, py, pz, pw, begin, end, lobes, out);
    case 4:
        return blocks<Weighted, 4>(px, py, pz, pw, begin, end, lobes, out);
    case 5:
        return blocks<Weighted, 5>(px, py, pz, pw, begin, end, lobes, out);
    case 6:
        return blocks<Weighted, 6>(px, py, pz, pw, begin, end, lobes, out);
    case 7:
        return blocks<Weighted, 7>(px, py, pz, pw, begin, end, lobes, out);
    case 8:
        return blocks<Weighted, 8>(px, py, pz, pw, begin, end, lobes, out);
    default:
        return blocks<Weighted, 0>(px, py, pz, pw, begin, end, lobes, out);
    }
}

} // namespace

bool eStepAvx2(const Samples& samples, size_t begin, size_t end, const LobeTerms& lobes,
               Moments& out) {
    forEachBlockRange(samples, begin, end,
                      [&](const float* x, const float* y, const float* z, const float* w,
                          size_t from, size_t to) {
                          if (w)
                              blocksAnyJ<true>(x, y, z, w, from, to, lobes, out);
                          else
                              blocksAnyJ<false>(x, y, z, nullptr, from, to, lobes, out);
                      });
    return true;
}

} // namespace ndfmip::vmf

#else

namespace ndfmip::vmf {
bool eStepAvx2(const Samples&, size_t, size_t, const LobeTerms&, Moments&) {
    return false;
}
} // namespace ndfmip::vmf

#endif
