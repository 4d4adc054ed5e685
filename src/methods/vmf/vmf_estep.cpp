// The E-step of spherical EM (Han et al. 2007, Algorithm 1, lines 3-7), the hot loop of the vMF
// fit: for eight normals at a time, the log-terms of every lobe in double, log-sum-exp, the
// responsibilities z_ij in float and their moments. This portable version is written with
// GCC/Clang vector extensions (SSE2 on x86-64); vmf_estep_avx2.cpp does the same in AVX2 + FMA,
// chosen at run time where the CPU has it.
#include <atomic>
#include <cstdint>
#include <cstring>

#include "methods/vmf/vmf_internal.h"

// Every helper taking or returning a vector is inlined into the kernels below, so no vector
// crosses a call boundary whose ABI depends on AVX being enabled.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace ndfmip::vmf {
namespace {

// Eight floats, or four doubles: one AVX register each (two SSE registers in the portable build).
using f8 = float __attribute__((vector_size(32)));
using f4 = float __attribute__((vector_size(16)));
using d4 = double __attribute__((vector_size(32)));
using u8 = uint32_t __attribute__((vector_size(32)));
using i8 = int32_t __attribute__((vector_size(32)));

#define NDFMIP_INLINE inline __attribute__((always_inline))

NDFMIP_INLINE f8 load8(const float* p) {
    f8 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

NDFMIP_INLINE f8 splat(float v) {
    return f8{} + v;
}

NDFMIP_INLINE d4 lowHalf(f8 v) {
    return __builtin_convertvector(__builtin_shufflevector(v, v, 0, 1, 2, 3), d4);
}
NDFMIP_INLINE d4 highHalf(f8 v) {
    return __builtin_convertvector(__builtin_shufflevector(v, v, 4, 5, 6, 7), d4);
}
NDFMIP_INLINE f8 join(d4 low, d4 high) {
    return __builtin_shufflevector(__builtin_convertvector(low, f4),
                                   __builtin_convertvector(high, f4), 0, 1, 2, 3, 4, 5, 6, 7);
}
NDFMIP_INLINE d4 maximum(d4 a, d4 b) {
    return a > b ? a : b;
}

// e^t for t <= 0, within 2 ulp: t = n ln2 + r, |r| <= ln2/2, e^r by Cephes' expf polynomial,
// 2^n built in the exponent bits. t < -87.3 (below the smallest normal float) gives 0.
NDFMIP_INLINE f8 expNonPositive(f8 t) {
    const f8 lowest = splat(-87.33f);
    i8 underflow = t < lowest;
    t = t < lowest ? lowest : t;
    // Adding 1.5 * 2^23 rounds t log2(e) to an integer n held in the low mantissa bits.
    const float shifter = 12582912.f;
    f8 k = t * 1.44269504088896341f + shifter;
    f8 n = k - shifter;
    // ln 2 split in two (Cephes C1 + C2) so that r = t - n ln2 is exact to float.
    f8 r = t - n * 0.693359375f + n * 2.12194440e-4f;
    f8 p = splat(1.9875691500e-4f);
    p = p * r + 1.3981999507e-3f;
    p = p * r + 8.3334519073e-3f;
    p = p * r + 4.1665795894e-2f;
    p = p * r + 1.6666665459e-1f;
    p = p * r + 5.0000001201e-1f;
    f8 y = p * (r * r) + r + 1.f;
    // The low bits of k are n + 0x400000 + exponent bits; << 23 keeps n + 127 in the exponent.
    u8 scale = ((u8)k + 127u) << 23;
    f8 result = y * (f8)scale;
    return underflow ? splat(0.f) : result;
}

// log(s) for 1 <= s (finite), within 2 ulp: s = m 2^e, m in [sqrt(1/2), sqrt(2)), log(m) by
// Cephes' logf polynomial in x = m - 1, plus e ln2 (split as in expNonPositive).
NDFMIP_INLINE f8 logAtLeastOne(f8 s) {
    u8 bits = (u8)s;
    i8 e = (i8)(bits >> 23) - 126;
    f8 m = (f8)((bits & 0x7fffffu) | 0x3f000000u); // [0.5, 1)
    i8 small = m < 0.707106781186547524f;
    e = small ? e - 1 : e;
    f8 x = small ? m + m - 1.f : m - 1.f;
    f8 z = x * x;
    f8 y = splat(7.0376836292e-2f);
    y = y * x - 1.1514610310e-1f;
    y = y * x + 1.1676998740e-1f;
    y = y * x - 1.2420140846e-1f;
    y = y * x + 1.4249322787e-1f;
    y = y * x - 1.6668057665e-1f;
    y = y * x + 2.0000714765e-1f;
    y = y * x - 2.4999993993e-1f;
    y = y * x + 3.3333331174e-1f;
    y = y * x * z;
    f8 fe = __builtin_convertvector(e, f8);
    y = y - fe * 2.12194440e-4f;
    y = y - 0.5f * z;
    return x + y + fe * 0.693359375f;
}

// One pass over [begin, end) (a multiple of 8 long): per-lane float sums of z and z n, flushed to
// the double `out` at the end (at most kChunk / 8 = 256 terms per lane, so float keeps ~1e-7).
template <bool Weighted>
NDFMIP_INLINE void eStepBlocks(const float* px, const float* py, const float* pz, const float* pw,
                               size_t begin, size_t end, const LobeTerms& lobes, Moments& out) {
    const int J = lobes.count;
    if (J < 1 || J > kMaxVmfLobes) __builtin_unreachable(); // runEm never passes an empty set
    f8 sumN[kMaxVmfLobes], sumX[kMaxVmfLobes], sumY[kMaxVmfLobes], sumZ[kMaxVmfLobes];
    for (int j = 0; j < J; ++j) sumN[j] = sumX[j] = sumY[j] = sumZ[j] = f8{};
    d4 sumLogLikelihood{};
    // log(alpha_j gamma_j(n)) of the low and high four normals of a block, then e^(s - max).
    d4 sLow[kMaxVmfLobes], sHigh[kMaxVmfLobes];
    f8 e[kMaxVmfLobes];

    for (size_t i = begin; i < end; i += 8) {
        f8 nx = load8(px + i), ny = load8(py + i), nz = load8(pz + i);
        d4 xLow = lowHalf(nx), yLow = lowHalf(ny), zLow = lowHalf(nz);
        d4 xHigh = highHalf(nx), yHigh = highHalf(ny), zHigh = highHalf(nz);
        for (int j = 0; j < J; ++j) {
            const double c = lobes.c[j], kx = lobes.kx[j], ky = lobes.ky[j], kz = lobes.kz[j];
            sLow[j] = c + kx * xLow + ky * yLow + kz * zLow;
            sHigh[j] = c + kx * xHigh + ky * yHigh + kz * zHigh;
        }
        d4 topLow = sLow[0], topHigh = sHigh[0];
        for (int j = 1; j < J; ++j) {
            topLow = maximum(topLow, sLow[j]);
            topHigh = maximum(topHigh, sHigh[j]);
        }
        // Log-sum-exp: the largest term is exactly 1, so sum >= 1 and log(sum) is well-behaved.
        f8 sum{};
        for (int j = 0; j < J; ++j) {
            e[j] = expNonPositive(join(sLow[j] - topLow, sHigh[j] - topHigh));
            sum += e[j];
        }
        f8 logSum = logAtLeastOne(sum);
        d4 logDensityLow = topLow + lowHalf(logSum), logDensityHigh = topHigh + highHalf(logSum);
        f8 scale = 1.f / sum;
        if constexpr (Weighted) {
            f8 w = load8(pw + i);
            scale *= w;
            sumLogLikelihood += logDensityLow * lowHalf(w) + logDensityHigh * highHalf(w);
        } else {
            sumLogLikelihood += logDensityLow + logDensityHigh;
        }
        for (int j = 0; j < J; ++j) {
            f8 z = e[j] * scale;
            sumN[j] += z;
            sumX[j] += z * (nx - lobes.mx[j]);
            sumY[j] += z * (ny - lobes.my[j]);
            sumZ[j] += z * (nz - lobes.mz[j]);
        }
    }

    auto total = [](f8 v) {
        double t = 0;
        for (int l = 0; l < 8; ++l) t += double(v[l]);
        return t;
    };
    for (int j = 0; j < J; ++j) {
        out.n[j] += total(sumN[j]);
        out.rx[j] += total(sumX[j]);
        out.ry[j] += total(sumY[j]);
        out.rz[j] += total(sumZ[j]);
    }
    out.logLikelihood +=
        (sumLogLikelihood[0] + sumLogLikelihood[1]) + (sumLogLikelihood[2] + sumLogLikelihood[3]);
}

bool cpuHasAvx2() {
#if defined(__x86_64__) && defined(__GNUC__)
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
    return false;
#endif
}

std::atomic<bool> useAvx2{cpuHasAvx2()};

} // namespace

void eStepPortable(const Samples& samples, size_t begin, size_t end, const LobeTerms& lobes,
                   Moments& out) {
    forEachBlockRange(samples, begin, end,
                      [&](const float* x, const float* y, const float* z, const float* w,
                          size_t from, size_t to) {
                          if (w)
                              eStepBlocks<true>(x, y, z, w, from, to, lobes, out);
                          else
                              eStepBlocks<false>(x, y, z, nullptr, from, to, lobes, out);
                      });
}

Kernel selectKernel(Kernel kernel) {
    bool avx2 = cpuHasAvx2() && kernel != Kernel::Portable;
    useAvx2.store(avx2);
    return avx2 ? Kernel::Avx2 : Kernel::Portable;
}

void eStep(const Samples& samples, size_t begin, size_t end, const LobeTerms& lobes, Moments& out) {
    if (!useAvx2.load(std::memory_order_relaxed) || !eStepAvx2(samples, begin, end, lobes, out))
        eStepPortable(samples, begin, end, lobes, out);
}

} // namespace ndfmip::vmf
