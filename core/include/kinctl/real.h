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

/* Sine and cosine of one angle; a backend may compute both at once. */
static inline void kc_sincos(kc_real x, kc_real *s, kc_real *c)
{
    *s = kc_sin(x);
    *c = kc_cos(x);
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

#endif /* KINCTL_REAL_H */
