/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl/real.h - the scalar type, the math it may use, and its tolerances.
 *
 * kc_real is double unless the library is built with KC_REAL_FLOAT defined
 * (CMake: -DKINCTL_REAL=float). This is the only header that includes
 * <math.h>: every other module reaches libm through the kc_ wrappers below,
 * so a fixed-point or CORDIC backend replaces libm in this one place.
 *
 * Mixing a float build of the library with a double build of its caller
 * fails at link time: kc_chain_init, the entry every use goes through, is
 * renamed per precision (see KC_PRECISION_SYMBOL).
 *
 * Tolerances are named per quantity and defined once per precision here.
 * All functions are pure and safe to call in the control cycle.
 */
#ifndef KINCTL_REAL_H
#define KINCTL_REAL_H

#include <math.h>
#include <stdint.h>

#include "kinctl/decls.h"

KC_BEGIN_DECLS

#ifdef KC_REAL_FLOAT
typedef float kc_real;
/* A literal in the build's precision: KC_R(0.5) is 0.5f in float builds. */
#define KC_R(x) (x##f)
#define KC_PRECISION_SYMBOL(name) name##_float
#define KC_REAL_NAME "float"
/* Largest finite value, and the unit roundoff. */
#define KC_REAL_MAX 3.402823466e+38f
#define KC_REAL_EPS 1.1920929e-07f
#else
typedef double kc_real;
#define KC_R(x) (x)
#define KC_PRECISION_SYMBOL(name) name##_double
#define KC_REAL_NAME "double"
#define KC_REAL_MAX 1.7976931348623157e+308
#define KC_REAL_EPS 2.220446049250313e-16
#endif

#define KC_PI KC_R(3.14159265358979323846)
#define KC_PI_2 KC_R(1.57079632679489661923)
#define KC_DEG KC_R(0.01745329251994329577) /* radians per degree */

/*
 * Tolerances. A rotation is "singular" for Euler-angle extraction when the
 * term that fixes the middle angle (cos(theta) for RPY, sin(theta) for Z-Y-Z)
 * is below KC_TOL_GIMBAL: the reference data uses 1e-10 in double; a float
 * matrix built from the same angles carries rounding of about 1e-7, so float
 * uses 1e-6.
 */
#ifdef KC_REAL_FLOAT
#define KC_TOL_GIMBAL KC_R(1e-6)
/* Below this sin(angle), an axis-angle or log axis is taken from R + R^T. */
#define KC_TOL_AXIS KC_R(1e-3)
/* Below this rotation angle (rad), series expansions replace sin(x)/x. */
#define KC_TOL_SMALL_ANGLE KC_R(1e-3)
/* Largest |R^T R - I| entry accepted as a rotation matrix from outside. */
#define KC_TOL_ORTHONORMAL KC_R(1e-5)
#else
#define KC_TOL_GIMBAL KC_R(1e-10)
#define KC_TOL_AXIS KC_R(1e-6)
#define KC_TOL_SMALL_ANGLE KC_R(1e-6)
#define KC_TOL_ORTHONORMAL KC_R(1e-9)
#endif

#ifdef KC_REAL_FLOAT
static inline kc_real kc_sqrt(kc_real x) { return sqrtf(x); }
static inline kc_real kc_sin(kc_real x) { return sinf(x); }
static inline kc_real kc_cos(kc_real x) { return cosf(x); }
static inline kc_real kc_atan2(kc_real y, kc_real x) { return atan2f(y, x); }
static inline kc_real kc_fabs(kc_real x) { return fabsf(x); }
static inline kc_real kc_hypot(kc_real x, kc_real y) { return hypotf(x, y); }
static inline kc_real kc_fmod(kc_real x, kc_real y) { return fmodf(x, y); }
static inline kc_real kc_floor(kc_real x) { return floorf(x); }
#else
static inline kc_real kc_sqrt(kc_real x) { return sqrt(x); }
static inline kc_real kc_sin(kc_real x) { return sin(x); }
static inline kc_real kc_cos(kc_real x) { return cos(x); }
static inline kc_real kc_atan2(kc_real y, kc_real x) { return atan2(y, x); }
static inline kc_real kc_fabs(kc_real x) { return fabs(x); }
static inline kc_real kc_hypot(kc_real x, kc_real y) { return hypot(x, y); }
static inline kc_real kc_fmod(kc_real x, kc_real y) { return fmod(x, y); }
static inline kc_real kc_floor(kc_real x) { return floor(x); }
#endif

/*
 * The real cube root, not libm's: C libraries' cbrt differ in the last bit
 * (glibc's and newlib's cbrtf do), and a plan computed from it would then
 * differ between this host and a board. The same IEEE operations on every
 * machine instead: the exponent divided by 3 on the bits of |x| (fdlibm's
 * first guess, within 3.4 %: its constants are (B - B/3 - 0.0330624) 2^M,
 * B the exponent bias, M the mantissa bits of the word), then Newton steps
 * y <- y - (y^3 - a) / (3 y^2), each squaring the relative error: 3 in
 * float (3.4e-2 -> 1.2e-3 -> 1.4e-6 -> 2e-12), 4 in double (-> 4e-24),
 * within an ulp or two. |x| below 2^-96 (subnormal in float) is scaled by
 * 2^96 first and the root by 2^-32 after (exact). 0, infinities and NaN
 * are returned as they are.
 */
static inline kc_real kc_cbrt(kc_real x)
{
    kc_real a = kc_fabs(x), scale = KC_R(1.0);
    if (!(a > KC_R(0.0)) || !(a < (kc_real)HUGE_VAL))
        return x;
    if (a < KC_R(1.2621774483536189e-29)) { /* 2^-96 */
        a *= KC_R(79228162514264337593543950336.0); /* 2^96 */
        scale = KC_R(2.3283064365386963e-10);       /* 2^-32 */
    }
#ifdef KC_REAL_FLOAT
    union {
        float f;
        uint32_t u;
    } b;
    b.f = a;
    b.u = b.u / 3u + 709958130u;
    const int steps = 3;
#else
    union {
        double f;
        uint64_t u;
    } b;
    b.f = a;
    b.u = ((b.u >> 32) / 3u + 715094163u) << 32;
    const int steps = 4;
#endif
    kc_real y = b.f;
    for (int i = 0; i < steps; i++)
        y -= (y * y * y - a) / (KC_R(3.0) * y * y);
    y *= scale;
    return x < KC_R(0.0) ? -y : y;
}

/*
 * Sine and cosine of one angle at once, the call every joint of every FK
 * makes. Not libm's: |x| <= 1e5 (64 in float) is reduced to r in
 * [-pi/4, pi/4] by Cody-Waite (pi/2 split into a short head, exact in
 * n * head, and tails), then sin r and cos r come from their Taylor series
 * through r^17 and r^18 (r^9 and r^10 in float), whose truncation error
 * ((pi/4)^19/19! < 1e-19 in double) is below the rounding: the error is
 * about 1 ulp (measured in tests/unit/test_real.c). Faster than a libm call, and the same
 * bits whatever libm the machine has, which replays and determinism hashes
 * rely on. Larger or non-finite x go to libm.
 */
/* sin r = r + r z (-1/3! + z (1/5! - z (1/7! ...))), z = r^2, by Horner. */
static inline kc_real kc_sincos_poly_sin(kc_real r, kc_real z)
{
#ifdef KC_REAL_FLOAT
    /* Float needs terms through r^9: (pi/4)^11/11! = 2e-9 < 2^-24. */
    kc_real p = KC_R(2.75573192239858906526e-6);
#else
    kc_real p = KC_R(2.8114572543455207632e-15);
    p = KC_R(-7.6471637318198164759e-13) + z * p;
    p = KC_R(1.60590438368216145994e-10) + z * p;
    p = KC_R(-2.50521083854417187751e-8) + z * p;
    p = KC_R(2.75573192239858906526e-6) + z * p;
#endif
    p = KC_R(-1.98412698412698412698e-4) + z * p;
    p = KC_R(8.33333333333333333333e-3) + z * p;
    p = KC_R(-1.66666666666666666667e-1) + z * p;
    return r + r * z * p;
}

/* cos r = 1 + z (-1/2! + z (1/4! - z (1/6! ...))). */
static inline kc_real kc_sincos_poly_cos(kc_real z)
{
#ifdef KC_REAL_FLOAT
    /* Float needs terms through r^10: (pi/4)^12/12! = 1e-10 < 2^-24. */
    kc_real p = KC_R(-2.75573192239858906526e-7);
#else
    kc_real p = KC_R(-1.56192069685862264622e-16);
    p = KC_R(4.77947733238738529744e-14) + z * p;
    p = KC_R(-1.14707455977297247139e-11) + z * p;
    p = KC_R(2.08767569878680989792e-9) + z * p;
    p = KC_R(-2.75573192239858906526e-7) + z * p;
#endif
    p = KC_R(2.48015873015873015873e-5) + z * p;
    p = KC_R(-1.38888888888888888889e-3) + z * p;
    p = KC_R(4.16666666666666666667e-2) + z * p;
    p = KC_R(-5.0e-1) + z * p;
    return KC_R(1.0) + z * p;
}

static inline void kc_sincos_inline(kc_real x, kc_real *s, kc_real *c)
{
#ifdef KC_REAL_FLOAT
    /* pi/2 = hi + mid + lo, hi with 17 bits: n hi is exact for |n| < 128. */
    const kc_real bound = KC_R(64.0);
    const kc_real pio2_hi = KC_R(1.5707855224609375), pio2_mid = KC_R(1.0804334124259185e-05),
                  pio2_lo = KC_R(-1.6513995574653217e-13);
#else
    /* pi/2 = hi + lo, hi with 33 bits: n hi is exact for |n| < 2^20. */
    const kc_real bound = KC_R(1e5);
    const kc_real pio2_hi = KC_R(1.57079632673412561417), pio2_mid = KC_R(6.07710050650619224932e-11),
                  pio2_lo = KC_R(0.0);
#endif
    if (!(kc_fabs(x) <= bound)) {
        *s = kc_sin(x);
        *c = kc_cos(x);
        return;
    }
    kc_real fn = x * KC_R(0.63661977236758134308); /* 2/pi */
    long n = (long)(fn + (fn < KC_R(0.0) ? KC_R(-0.5) : KC_R(0.5)));
    kc_real nr = (kc_real)n;
    kc_real r = ((x - nr * pio2_hi) - nr * pio2_mid) - nr * pio2_lo;
    kc_real z = r * r;
    kc_real sr = kc_sincos_poly_sin(r, z), cr = kc_sincos_poly_cos(z);
    switch (n & 3) {
    case 0: *s = sr; *c = cr; break;
    case 1: *s = cr; *c = -sr; break;
    case 2: *s = -sr; *c = -cr; break;
    default: *s = -cr; *c = sr; break;
    }
}

/*
 * kc_sincos: the above, called where code is built for size
 * (__OPTIMIZE_SIZE__, -Os): one copy of it in the library (src/real.c)
 * instead of one inlined into each of the seven modules that use it (1.9 KB
 * on a Cortex-M4F). The FK walk, which runs it for every joint of every
 * call, inlines kc_sincos_inline itself. The same operations either way:
 * the same bits.
 */
void kc_sincos_outline(kc_real x, kc_real *s, kc_real *c);

static inline void kc_sincos(kc_real x, kc_real *s, kc_real *c)
{
#ifdef __OPTIMIZE_SIZE__
    kc_sincos_outline(x, s, c);
#else
    kc_sincos_inline(x, s, c);
#endif
}

/* Nonzero when x is neither NaN nor infinite. */
static inline int kc_isfinite(kc_real x) { return isfinite(x) != 0; }

static inline kc_real kc_min(kc_real a, kc_real b) { return a < b ? a : b; }
static inline kc_real kc_max(kc_real a, kc_real b) { return a > b ? a : b; }

static inline kc_real kc_clamp(kc_real x, kc_real lo, kc_real hi)
{
    return x < lo ? lo : (x > hi ? hi : x);
}

/* Wraps an angle into (-pi, pi]. */
static inline kc_real kc_wrap_angle(kc_real a)
{
    kc_real w = a - KC_R(2.0) * KC_PI * kc_floor((a + KC_PI) / (KC_R(2.0) * KC_PI));
    return w <= -KC_PI ? w + KC_R(2.0) * KC_PI : w;
}

KC_END_DECLS

#endif /* KINCTL_REAL_H */
