/* SPDX-License-Identifier: BSD-3-Clause */
/* test_zone.c - link volumes against forbidden zones (kinctl/zone.h).
 *
 * The reference is computed here, in double, independently of zone.c:
 *   - closed forms where a pair has one: a ball against any zone (the
 *     zone's point distance at the centre minus the radius), a capsule
 *     against a sphere (segment-point distance), any volume against a
 *     half-space (its lowest vertex, or the cylinder's closed form);
 *   - brute force otherwise: the volume is sampled on a grid of its
 *     parameters that covers its boundary, and the exact distance of each
 *     sample point to the zone (box: clamping, cylinder: the (rho, z)
 *     rectangle, sphere, half-space) is taken. The minimum is never below
 *     the true distance and exceeds it by at most the grid's step h, so
 *     the library's value must lie in [ref - h - tol, ref + tol]. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "testutil.h"

#ifdef KC_REAL_FLOAT
/* KC_ZONE_TOL plus the rounding of float poses of size ~2 m. */
#define TOL_D 6e-5
#else
#define TOL_D 1e-8
#endif

#define N_POSES 40
#define GRID 24

typedef struct dv3 {
    double x, y, z;
} dv3;

/* World point of a local point of a shape's frame, in double. */
static dv3 to_world(const kc_shape *s, double x, double y, double z)
{
    const kc_real(*R)[3] = s->pose.R.m;
    dv3 w;
    w.x = (double)R[0][0] * x + (double)R[0][1] * y + (double)R[0][2] * z + (double)s->pose.t.v[0];
    w.y = (double)R[1][0] * x + (double)R[1][1] * y + (double)R[1][2] * z + (double)s->pose.t.v[1];
    w.z = (double)R[2][0] * x + (double)R[2][1] * y + (double)R[2][2] * z + (double)s->pose.t.v[2];
    return w;
}

static dv3 to_local(const kc_shape *s, dv3 p)
{
    const kc_real(*R)[3] = s->pose.R.m;
    double d[3] = {p.x - (double)s->pose.t.v[0], p.y - (double)s->pose.t.v[1], p.z - (double)s->pose.t.v[2]};
    dv3 l;
    l.x = (double)R[0][0] * d[0] + (double)R[1][0] * d[1] + (double)R[2][0] * d[2];
    l.y = (double)R[0][1] * d[0] + (double)R[1][1] * d[1] + (double)R[2][1] * d[2];
    l.z = (double)R[0][2] * d[0] + (double)R[1][2] * d[1] + (double)R[2][2] * d[2];
    return l;
}

static double dmax(double a, double b) { return a > b ? a : b; }

/* Exact distance from a point to a zone (0 inside). */
static double point_zone(const kc_shape *z, dv3 p)
{
    dv3 l = to_local(z, p);
    const kc_real *d = z->dim;
    switch (z->kind) {
    case KC_SHAPE_SPHERE: return dmax(sqrt(l.x * l.x + l.y * l.y + l.z * l.z) - (double)d[0], 0.0);
    case KC_SHAPE_BOX: {
        double ex = dmax(fabs(l.x) - (double)d[0], 0.0), ey = dmax(fabs(l.y) - (double)d[1], 0.0),
               ez = dmax(fabs(l.z) - (double)d[2], 0.0);
        return sqrt(ex * ex + ey * ey + ez * ez);
    }
    case KC_SHAPE_CYLINDER: {
        double er = dmax(sqrt(l.x * l.x + l.y * l.y) - (double)d[0], 0.0), ez = dmax(fabs(l.z) - (double)d[1], 0.0);
        return sqrt(er * er + ez * ez);
    }
    case KC_SHAPE_HALFSPACE: return dmax(l.z, 0.0);
    }
    fail_msg("unknown zone kind %d", z->kind);
    return 0.0;
}

/* Minimum over a grid covering the volume's boundary, and the grid's step
 * bound h (the farthest a boundary point can be from its nearest sample). */
static double brute(const kc_shape *v, const kc_shape *z, double *h)
{
    const kc_real *d = v->dim;
    double best = HUGE_VAL;
    const int n = GRID;
    double st = 1.0 / (double)(n - 1);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            for (int k = 0; k < n; k++) {
                double u = i * st, w = j * st, t = k * st;
                double x, y, zz;
                switch (v->kind) {
                case KC_SHAPE_BOX:
                    x = (2 * u - 1) * (double)d[0];
                    y = (2 * w - 1) * (double)d[1];
                    zz = (2 * t - 1) * (double)d[2];
                    break;
                case KC_SHAPE_FRUSTUM: {
                    double ax = (double)d[0] + ((double)d[2] - (double)d[0]) * t;
                    double ay = (double)d[1] + ((double)d[3] - (double)d[1]) * t;
                    x = (2 * u - 1) * ax;
                    y = (2 * w - 1) * ay;
                    zz = (2 * t - 1) * (double)d[4];
                    break;
                }
                case KC_SHAPE_CYLINDER:
                    x = u * (double)d[0] * cos(2 * KT_PI * w);
                    y = u * (double)d[0] * sin(2 * KT_PI * w);
                    zz = (2 * t - 1) * (double)d[1];
                    break;
                case KC_SHAPE_CAPSULE: {
                    /* the sphere of radius r about the axis point t */
                    double th = KT_PI * u, ph = 2 * KT_PI * w;
                    x = (double)d[0] * sin(th) * cos(ph);
                    y = (double)d[0] * sin(th) * sin(ph);
                    zz = (2 * t - 1) * (double)d[1] + (double)d[0] * cos(th);
                    break;
                }
                default: fail_msg("unknown volume kind %d", v->kind); return 0.0;
                }
                double dd = point_zone(z, to_world(v, x, y, zz));
                if (dd < best)
                    best = dd;
            }
    /* A grid cell's diagonal in each parametrisation. */
    switch (v->kind) {
    case KC_SHAPE_BOX:
        *h = 2 * st * sqrt((double)(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
        break;
    case KC_SHAPE_FRUSTUM: {
        double ax = dmax((double)d[0], (double)d[2]), ay = dmax((double)d[1], (double)d[3]);
        /* plus the slant between layers */
        *h = 2 * st * sqrt(ax * ax + ay * ay + (double)(d[4] * d[4])) + 2 * st * (fabs((double)(d[0] - d[2])) + fabs((double)(d[1] - d[3])));
        break;
    }
    case KC_SHAPE_CYLINDER:
        *h = st * sqrt(pow(2 * KT_PI * (double)d[0], 2) + pow((double)d[0], 2) + pow(2 * (double)d[1], 2));
        break;
    default:
        *h = st * sqrt(pow(KT_PI * (double)d[0], 2) + pow(2 * KT_PI * (double)d[0], 2) + pow(2 * (double)d[1], 2));
        break;
    }
    return best;
}

static double lib_dist(const kc_shape *a, const kc_shape *b)
{
    kc_real d = KC_R(-1.0);
    assert_int_equal(kc_shape_distance(a, b, &d), KC_OK);
    kc_real d2 = KC_R(-1.0);
    assert_int_equal(kc_shape_distance(b, a, &d2), KC_OK); /* symmetric */
    kt_near((double)d, (double)d2, TOL_D, "distance symmetric");
    return (double)d;
}

/* A random shape of the kind, sizes 0.02..0.3 m, at a pose near the origin
 * (within 0.6 m, so that pairs come near, touch and overlap). */
static kc_shape rand_shape(kt_rng *r, int kind)
{
    kc_shape s;
    memset(&s, 0, sizeof s);
    s.kind = kind;
    s.pose = kt_rand_pose(r);
    for (int i = 0; i < 3; i++)
        s.pose.t.v[i] = (kc_real)(0.3 * (double)s.pose.t.v[i]);
    for (int i = 0; i < KC_SHAPE_DIMS; i++)
        s.dim[i] = (kc_real)kt_uniform(r, 0.02, 0.3);
    if (kind == KC_SHAPE_SPHERE)
        s.dim[1] = s.dim[2] = s.dim[3] = s.dim[4] = KC_R(0.0);
    if (kind == KC_SHAPE_CAPSULE || kind == KC_SHAPE_CYLINDER)
        s.dim[2] = s.dim[3] = s.dim[4] = KC_R(0.0);
    if (kind == KC_SHAPE_BOX)
        s.dim[3] = s.dim[4] = KC_R(0.0);
    if (kind == KC_SHAPE_HALFSPACE)
        for (int i = 0; i < KC_SHAPE_DIMS; i++)
            s.dim[i] = KC_R(0.0);
    assert_int_equal(kc_shape_check(&s, 1), KC_OK);
    return s;
}

static const int volume_kinds[] = {KC_SHAPE_CAPSULE, KC_SHAPE_CYLINDER, KC_SHAPE_BOX, KC_SHAPE_FRUSTUM};
static const int zone_kinds[] = {KC_SHAPE_BOX, KC_SHAPE_SPHERE, KC_SHAPE_CYLINDER, KC_SHAPE_HALFSPACE};

static void test_against_brute_force(void **state)
{
    (void)state;
    kt_rng rng = kt_rng_make(8001);
    int overlaps = 0, apart = 0;
    for (int a = 0; a < 4; a++)
        for (int b = 0; b < 4; b++)
            for (int n = 0; n < N_POSES; n++) {
                kc_shape v = rand_shape(&rng, volume_kinds[a]), z = rand_shape(&rng, zone_kinds[b]);
                double h = 0.0, ref = brute(&v, &z, &h), got = lib_dist(&v, &z);
                char what[96];
                snprintf(what, sizeof what, "volume %d vs zone %d, pose %d: not above the sampled minimum", v.kind,
                         z.kind, n);
                /* never more than the truth (which is <= ref) */
                if (got > ref + TOL_D)
                    kt_near(got, ref, TOL_D, what);
                snprintf(what, sizeof what, "volume %d vs zone %d, pose %d: within the grid step", v.kind, z.kind, n);
                if (got < ref - h - TOL_D)
                    kt_near(got, ref, h + TOL_D, what);
                kt_checks += 2;
                if (ref == 0.0)
                    overlaps++;
                else
                    apart++;
            }
    /* The poses must exercise both outcomes. */
    assert_true(overlaps > 60);
    assert_true(apart > 200);
}

/* Exact cases: a ball against every zone kind, a capsule against a sphere
 * and against a half-space, boxes and frusta against a half-space (lowest
 * vertex), a cylinder against a half-space (closed form). */
static void test_closed_forms(void **state)
{
    (void)state;
    kt_rng rng = kt_rng_make(8002);
    for (int n = 0; n < 400; n++) {
        kc_shape ball = rand_shape(&rng, KC_SHAPE_SPHERE);
        dv3 c = to_world(&ball, 0, 0, 0);
        for (int b = 0; b < 4; b++) {
            kc_shape z = rand_shape(&rng, zone_kinds[b]);
            kt_near(lib_dist(&ball, &z), dmax(point_zone(&z, c) - (double)ball.dim[0], 0.0), TOL_D, "ball vs zone");
        }
        kc_shape cap = rand_shape(&rng, KC_SHAPE_CAPSULE), sph = rand_shape(&rng, KC_SHAPE_SPHERE);
        {
            dv3 p0 = to_world(&cap, 0, 0, -(double)cap.dim[1]), p1 = to_world(&cap, 0, 0, (double)cap.dim[1]);
            dv3 s = to_world(&sph, 0, 0, 0);
            double ab[3] = {p1.x - p0.x, p1.y - p0.y, p1.z - p0.z}, as[3] = {s.x - p0.x, s.y - p0.y, s.z - p0.z};
            double t = (ab[0] * as[0] + ab[1] * as[1] + ab[2] * as[2]) / (ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2]);
            t = t < 0 ? 0 : (t > 1 ? 1 : t);
            double e[3] = {as[0] - t * ab[0], as[1] - t * ab[1], as[2] - t * ab[2]};
            double ref = dmax(sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]) - (double)cap.dim[0] - (double)sph.dim[0], 0.0);
            kt_near(lib_dist(&cap, &sph), ref, TOL_D, "capsule vs sphere");
        }
        kc_shape hs = rand_shape(&rng, KC_SHAPE_HALFSPACE);
        {
            double lo = fmin(to_local(&hs, to_world(&cap, 0, 0, -(double)cap.dim[1])).z,
                             to_local(&hs, to_world(&cap, 0, 0, (double)cap.dim[1])).z);
            kt_near(lib_dist(&cap, &hs), dmax(lo - (double)cap.dim[0], 0.0), TOL_D, "capsule vs half-space");
        }
        kc_shape box = rand_shape(&rng, KC_SHAPE_BOX), fr = rand_shape(&rng, KC_SHAPE_FRUSTUM);
        {
            double lo_b = HUGE_VAL, lo_f = HUGE_VAL;
            for (int k = 0; k < 8; k++) {
                double sx = (k & 1) ? 1 : -1, sy = (k & 2) ? 1 : -1, sz = (k & 4) ? 1 : -1;
                dv3 pb = to_world(&box, sx * (double)box.dim[0], sy * (double)box.dim[1], sz * (double)box.dim[2]);
                lo_b = fmin(lo_b, to_local(&hs, pb).z);
                double hx = sz > 0 ? (double)fr.dim[2] : (double)fr.dim[0], hy = sz > 0 ? (double)fr.dim[3] : (double)fr.dim[1];
                dv3 pf = to_world(&fr, sx * hx, sy * hy, sz * (double)fr.dim[4]);
                lo_f = fmin(lo_f, to_local(&hs, pf).z);
            }
            kt_near(lib_dist(&box, &hs), dmax(lo_b, 0.0), TOL_D, "box vs half-space");
            kt_near(lib_dist(&fr, &hs), dmax(lo_f, 0.0), TOL_D, "frustum vs half-space");
        }
        kc_shape cyl = rand_shape(&rng, KC_SHAPE_CYLINDER);
        {
            /* n.c - h |n.a| - r sqrt(1 - (n.a)^2), n the plane's normal, a
             * the cylinder's axis, both in world */
            dv3 c0 = to_world(&cyl, 0, 0, 0), a1 = to_world(&cyl, 0, 0, 1);
            dv3 cl = to_local(&hs, c0), al = to_local(&hs, a1);
            double na = al.z - cl.z;
            double ref = cl.z - (double)cyl.dim[1] * fabs(na) - (double)cyl.dim[0] * sqrt(dmax(1 - na * na, 0.0));
            kt_near(lib_dist(&cyl, &hs), dmax(ref, 0.0), TOL_D, "cylinder vs half-space");
        }
    }
}

/* Touching and nested shapes: 0; a box just clear of a box face: the gap. */
static void test_special_cases(void **state)
{
    (void)state;
    kc_shape a, b;
    memset(&a, 0, sizeof a);
    a.kind = KC_SHAPE_BOX;
    kc_pose_identity(&a.pose);
    a.dim[0] = a.dim[1] = a.dim[2] = KC_R(0.5);
    b = a;
    b.dim[0] = b.dim[1] = b.dim[2] = KC_R(0.1);
    kt_near(lib_dist(&a, &b), 0.0, 0.0, "box inside a box");
    b.pose.t.v[0] = KC_R(0.7);
    kt_near(lib_dist(&a, &b), 0.1, TOL_D, "face to face");
    b.pose.t.v[1] = KC_R(0.7);
    kt_near(lib_dist(&a, &b), sqrt(0.02), TOL_D, "edge to edge");
    b.pose.t.v[2] = KC_R(0.7);
    kt_near(lib_dist(&a, &b), sqrt(0.03), TOL_D, "corner to corner");
    /* a cylinder lying across a box, parallel to its face */
    kc_vec3 p0 = kc_vec3_make(KC_R(-1.0), KC_R(0.0), KC_R(0.8)), p1 = kc_vec3_make(KC_R(1.0), KC_R(0.0), KC_R(0.8));
    assert_int_equal(kc_shape_segment(KC_SHAPE_CYLINDER, &p0, &p1, KC_R(0.1), &b), KC_OK);
    kt_near(lib_dist(&a, &b), 0.2, TOL_D, "cylinder across a box");
    /* errors */
    kc_real d = KC_R(7.0);
    kc_shape h1, h2;
    memset(&h1, 0, sizeof h1);
    h1.kind = KC_SHAPE_HALFSPACE;
    kc_pose_identity(&h1.pose);
    h2 = h1;
    assert_int_equal(kc_shape_distance(&h1, &h2, &d), KC_E_ARG);
    assert_true(d == KC_R(7.0));
    assert_int_equal(kc_shape_check(&h1, 0), KC_E_ARG); /* not a link volume */
    assert_int_equal(kc_shape_check(&h1, 1), KC_OK);
    a.dim[1] = KC_R(0.0);
    assert_int_equal(kc_shape_check(&a, 1), KC_E_ARG);
    a.dim[1] = (kc_real)NAN;
    assert_int_equal(kc_shape_check(&a, 1), KC_E_ARG);
    assert_int_equal(kc_shape_segment(KC_SHAPE_CAPSULE, &p0, &p0, KC_R(0.1), &b), KC_E_ARG);
    assert_int_equal(kc_shape_segment(KC_SHAPE_BOX, &p0, &p1, KC_R(0.1), &b), KC_E_ARG);
    kc_zone_set set;
    kc_zone_set_init(&set);
    for (int i = 0; i < KC_ZONE_MAX; i++)
        assert_int_equal(kc_zone_set_add(&set, &h1), KC_OK);
    assert_int_equal(kc_zone_set_add(&set, &h1), KC_E_CAPACITY);
    assert_int_equal(set.n_zones, KC_ZONE_MAX);
    assert_int_equal(kc_zone_set_check(&set), KC_OK);
    set.margin = KC_R(-0.1);
    assert_int_equal(kc_zone_set_check(&set), KC_E_ARG);
}

/* A zone set of the kinds, around a model's workspace. */
static void some_zones(kt_rng *r, kc_zone_set *set, int n)
{
    kc_zone_set_init(set);
    for (int i = 0; i < n; i++) {
        kc_shape z = rand_shape(r, zone_kinds[i % 4]);
        for (int k = 0; k < 3; k++)
            z.pose.t.v[k] = (kc_real)(3.0 * (double)z.pose.t.v[k]); /* within ~1.8 m */
        if (z.kind == KC_SHAPE_HALFSPACE)
            z.pose.t.v[2] = (kc_real)(kt_uniform(r, -1.5, -0.5)); /* mostly clear */
        assert_int_equal(kc_zone_set_add(set, &z), KC_OK);
    }
}

/* kc_zone_check names the closest pair, exact below margin + near, and its
 * verdict is the margin's; every built-in model has valid volumes. */
static void test_check_on_models(void **state)
{
    (void)state;
    kt_rng rng = kt_rng_make(8003);
    int violations = 0, clear = 0;
    for (int m = 0; m < KC_MODEL_COUNT; m++) {
        kc_chain c;
        assert_int_equal(kc_chain_init_model(&c, (kc_model)m, NULL), KC_OK);
        assert_true(c.n_volumes >= 2);
        for (int n = 0; n < 100; n++) {
            kc_zone_set set;
            some_zones(&rng, &set, 10);
            kc_real q[KC_MAX_JOINTS], dist[KC_MAX_VOLUMES * KC_ZONE_MAX];
            kt_rand_q(&rng, &c, q);
            assert_int_equal(kc_zone_distances(&c, &set, q, dist), KC_OK);
            double best = HUGE_VAL;
            int bi = -1;
            for (int i = 0; i < c.n_volumes * set.n_zones; i++)
                if ((double)dist[i] < best) {
                    best = (double)dist[i];
                    bi = i;
                }
            kc_zone_hit hit;
            kc_status st = kc_zone_check(&c, &set, q, NULL, &hit);
            if (best < (double)(set.margin + set.near)) {
                kt_near((double)hit.distance, best, 0.0, "closest pair's distance");
                assert_int_equal(hit.volume * set.n_zones + hit.zone, bi);
            } else {
                assert_true((double)hit.distance <= best);
                assert_true((double)hit.distance >= (double)(set.margin + set.near));
            }
            assert_int_equal(st, best < (double)set.margin ? KC_E_LIMIT : KC_OK);
            if (st == KC_E_LIMIT)
                violations++;
            else
                clear++;
            /* the same with the caller's frames */
            kc_pose frames[KC_MAX_FRAMES];
            kc_zone_hit hit2;
            kc_fk_frames(&c, q, frames, NULL);
            assert_int_equal(kc_zone_check(&c, &set, q, frames, &hit2), st);
            assert_true(hit2.distance == hit.distance);
        }
    }
    assert_true(violations > 50);
    assert_true(clear > 50);
    /* no zones: nothing to hit */
    kc_chain c;
    kc_zone_set empty;
    kc_zone_hit hit;
    kc_real q[KC_MAX_JOINTS] = {0};
    kc_zone_set_init(&empty);
    assert_int_equal(kc_chain_init_model(&c, KC_MODEL_PUMA560, NULL), KC_OK);
    assert_int_equal(kc_zone_check(&c, &empty, q, NULL, &hit), KC_OK);
    assert_int_equal(hit.volume, -1);
    q[2] = (kc_real)NAN;
    assert_int_equal(kc_zone_check(&c, &empty, q, NULL, &hit), KC_E_ARG);
}

/* Points of the volumes on support directions, in world. */
static void volume_points(const kc_chain *c, const kc_real *q, dv3 *pts, int per)
{
    kc_pose frames[KC_MAX_FRAMES];
    kc_shape w[KC_MAX_VOLUMES];
    kc_fk_frames(c, q, frames, NULL);
    kc_zone_volumes_world(c, frames, w);
    kt_rng r = kt_rng_make(77);
    for (int i = 0; i < c->n_volumes; i++)
        for (int k = 0; k < per; k++) {
            /* a point of the volume: along a fixed random local direction,
             * at its bounding radius scaled into the shape's box */
            double x = kt_uniform(&r, -1, 1), y = kt_uniform(&r, -1, 1), z = kt_uniform(&r, -1, 1);
            const kc_real *d = w[i].dim;
            double sx = (double)d[0], sy = w[i].kind == KC_SHAPE_BOX ? (double)d[1] : (double)d[0];
            double sz = w[i].kind == KC_SHAPE_BOX ? (double)d[2] : (double)d[1];
            if (w[i].kind == KC_SHAPE_FRUSTUM) {
                sx = fmin((double)d[0], (double)d[2]);
                sy = fmin((double)d[1], (double)d[3]);
                sz = (double)d[4];
            }
            pts[i * per + k] = to_world(&w[i], 0.7 * x * sx, 0.7 * y * sy, z * sz);
        }
}

/* The travel bound: no point of a volume moves farther than
 * sum |dq_j| lever_j, on random small motions of every model. */
static void test_travel_bound(void **state)
{
    (void)state;
    kt_rng rng = kt_rng_make(8004);
    enum { PER = 8 };
    for (int m = 0; m < KC_MODEL_COUNT; m++) {
        kc_chain c;
        kc_real lever[KC_MAX_JOINTS];
        assert_int_equal(kc_chain_init_model(&c, (kc_model)m, NULL), KC_OK);
        kc_zone_levers(&c, lever);
        double tight = 0.0;
        for (int n = 0; n < 300; n++) {
            kc_real q0[KC_MAX_JOINTS], q1[KC_MAX_JOINTS];
            kt_rand_q(&rng, &c, q0);
            double bound = 0.0;
            for (int j = 0; j < c.n_joints; j++) {
                double dq = kt_uniform(&rng, -0.01, 0.01);
                q1[j] = (kc_real)((double)q0[j] + dq);
                bound += fabs((double)q1[j] - (double)q0[j]) * (double)lever[j];
            }
            dv3 a[KC_MAX_VOLUMES * PER], b[KC_MAX_VOLUMES * PER];
            volume_points(&c, q0, a, PER);
            volume_points(&c, q1, b, PER);
            for (int i = 0; i < c.n_volumes * PER; i++) {
                double mv = sqrt(pow(a[i].x - b[i].x, 2) + pow(a[i].y - b[i].y, 2) + pow(a[i].z - b[i].z, 2));
                /* a chord is shorter than its arc: the bound holds for the
                 * straight displacement too */
                assert_true(mv <= bound + 1e-5);
                tight = dmax(tight, mv / bound);
                kt_checks++;
            }
        }
        /* and it is not absurdly loose */
        assert_true(tight > 0.2);
        kc_real travel = kc_zone_tick_travel(&c, KC_R(0.001));
        double expect = 0.0;
        for (int j = 0; j < c.n_joints; j++)
            expect += (double)c.joints[j].limits.qd_max * 0.001 * (double)lever[j];
        kt_near((double)travel, expect, 1e-12 + 1e-6 * expect, "tick travel");
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_against_brute_force),
        cmocka_unit_test(test_closed_forms),
        cmocka_unit_test(test_special_cases),
        cmocka_unit_test(test_check_on_models),
        cmocka_unit_test(test_travel_bound),
    };
    int failed = cmocka_run_group_tests_name("zone (" KC_REAL_NAME ")", tests, NULL, NULL);
    kt_report("zone");
    return failed;
}
