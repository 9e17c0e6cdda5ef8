/* SPDX-License-Identifier: BSD-3-Clause */
/* chain.c - building and checking robot models (seed 003's coded chains,
 * seed 000's DH rows) and the built-in arms. */
#include "kinctl/chain.h"

#include <string.h>

#define INF ((kc_real)INFINITY)

kc_joint_limits kc_joint_limits_default(void)
{
    kc_joint_limits l = {-INF, INF, INF, INF, INF};
    return l;
}

kc_status kc_chain_init(kc_chain *chain)
{
    if (chain == NULL)
        return KC_E_ARG;
    memset(chain, 0, sizeof *chain);
    kc_pose_identity(&chain->base);
    kc_pose_identity(&chain->tool);
    return KC_OK;
}

kc_status kc_chain_check_limits(const kc_joint_limits *l)
{
    if (l == NULL)
        return KC_E_ARG;
    /* Written with ! so that NaN fails every comparison into an error. */
    if (!(l->q_min <= l->q_max))
        return KC_E_ARG;
    if (!(l->qd_max > KC_R(0.0)) || !(l->qdd_max > KC_R(0.0)) || !(l->qddd_max > KC_R(0.0)))
        return KC_E_ARG;
    /* An infinite lower bound must be -inf and an infinite upper one +inf. */
    if (l->q_min == INF || l->q_max == -INF)
        return KC_E_ARG;
    return KC_OK;
}

static int is_joint_code(int code) { return code >= KC_CODE_RX_JOINT && code <= KC_CODE_TZ_JOINT; }
static int is_const_code(int code) { return code >= KC_CODE_RX && code <= KC_CODE_TZ; }

static kc_status push_element(kc_chain *chain, int code, int joint, kc_real value)
{
    if (chain->n_elements >= KC_MAX_ELEMENTS)
        return KC_E_CAPACITY;
    kc_element *e = &chain->elements[chain->n_elements++];
    e->code = (uint8_t)code;
    e->joint = (int8_t)joint;
    e->value = value;
    e->c = KC_R(1.0);
    e->s = KC_R(0.0);
    e->quarter = 0;
    if (code >= KC_CODE_RX && code <= KC_CODE_RZ) {
        kc_sincos(value, &e->s, &e->c);
        /* DH tables are full of alpha = +-pi/2, whose cosine comes out as
         * rounding noise: take it as the exact quarter turn it stands for. */
        if (kc_fabs(e->c) <= KC_REAL_EPS && kc_fabs(e->s) == KC_R(1.0)) {
            e->quarter = e->s > KC_R(0.0) ? 1 : -1;
            e->c = KC_R(0.0);
        }
    }
    return KC_OK;
}

kc_status kc_chain_add_frame(kc_chain *chain)
{
    if (chain == NULL)
        return KC_E_ARG;
    if (chain->n_frames >= KC_MAX_FRAMES)
        return KC_E_CAPACITY;
    chain->frame_end[chain->n_frames++] = (uint8_t)chain->n_elements;
    return KC_OK;
}

kc_status kc_chain_add_joint(kc_chain *chain, kc_code code, kc_real offset, const kc_joint_limits *limits)
{
    if (chain == NULL || !is_joint_code((int)code) || !kc_isfinite(offset))
        return KC_E_ARG;
    kc_joint_limits def = kc_joint_limits_default();
    if (limits == NULL)
        limits = &def;
    if (kc_chain_check_limits(limits) != KC_OK)
        return KC_E_ARG;
    if (chain->n_joints >= KC_MAX_JOINTS || chain->n_elements >= KC_MAX_ELEMENTS ||
        chain->n_frames >= KC_MAX_FRAMES)
        return KC_E_CAPACITY;
    kc_joint *j = &chain->joints[chain->n_joints];
    j->type = code <= KC_CODE_RZ_JOINT ? KC_JOINT_REVOLUTE : KC_JOINT_PRISMATIC;
    j->offset = offset;
    j->limits = *limits;
    push_element(chain, (int)code, chain->n_joints, KC_R(0.0));
    chain->n_joints++;
    return kc_chain_add_frame(chain);
}

kc_status kc_chain_add_const(kc_chain *chain, kc_code code, kc_real value)
{
    if (chain == NULL || !is_const_code((int)code) || !kc_isfinite(value))
        return KC_E_ARG;
    if (value == KC_R(0.0))
        return KC_OK; /* the identity: dropped, frames keep their numbers */
    return push_element(chain, (int)code, -1, value);
}

kc_status kc_chain_add_code(kc_chain *chain, int code, kc_real arg)
{
    if (chain == NULL || !kc_isfinite(arg))
        return KC_E_ARG;
    if (is_joint_code(code)) {
        if (arg != (kc_real)chain->n_joints)
            return KC_E_ARG;
        return kc_chain_add_joint(chain, (kc_code)code, KC_R(0.0), NULL);
    }
    if (!is_const_code(code))
        return KC_E_ARG;
    if (chain->n_frames >= KC_MAX_FRAMES)
        return KC_E_CAPACITY;
    kc_status st = kc_chain_add_const(chain, (kc_code)code, arg);
    if (st != KC_OK)
        return st;
    return kc_chain_add_frame(chain);
}

/* Room for one more DH link: a joint, up to four elements and a frame. */
static kc_status dh_room(const kc_chain *chain, const kc_dh_row *row)
{
    if (chain == NULL || row == NULL)
        return KC_E_ARG;
    if (!kc_isfinite(row->a) || !kc_isfinite(row->alpha) || !kc_isfinite(row->d) || !kc_isfinite(row->theta))
        return KC_E_ARG;
    if (row->type != KC_JOINT_REVOLUTE && row->type != KC_JOINT_PRISMATIC)
        return KC_E_ARG;
    if (kc_chain_check_limits(&row->limits) != KC_OK)
        return KC_E_ARG;
    if (chain->n_joints >= KC_MAX_JOINTS || chain->n_elements + 4 > KC_MAX_ELEMENTS ||
        chain->n_frames >= KC_MAX_FRAMES)
        return KC_E_CAPACITY;
    return KC_OK;
}

/* The joint's own transform of a DH row, and the constant that is replaced
 * by the joint (theta for revolute, d for prismatic) as its offset. */
static void add_dh_joint(kc_chain *chain, const kc_dh_row *row)
{
    int revolute = row->type == KC_JOINT_REVOLUTE;
    kc_joint *j = &chain->joints[chain->n_joints];
    j->type = row->type;
    j->offset = revolute ? row->theta : row->d;
    j->limits = row->limits;
    push_element(chain, revolute ? KC_CODE_RZ_JOINT : KC_CODE_TZ_JOINT, chain->n_joints, KC_R(0.0));
    chain->n_joints++;
    /* The other of theta and d stays constant. */
    kc_chain_add_const(chain, revolute ? KC_CODE_TZ : KC_CODE_RZ, revolute ? row->d : row->theta);
}

kc_status kc_chain_add_dh(kc_chain *chain, const kc_dh_row *row)
{
    kc_status st = dh_room(chain, row);
    if (st != KC_OK)
        return st;
    add_dh_joint(chain, row); /* Rz(theta) Tz(d), or Tz(d) Rz(theta): they commute */
    kc_chain_add_const(chain, KC_CODE_TX, row->a);
    kc_chain_add_const(chain, KC_CODE_RX, row->alpha);
    return kc_chain_add_frame(chain);
}

kc_status kc_chain_add_mdh(kc_chain *chain, const kc_dh_row *row)
{
    kc_status st = dh_room(chain, row);
    if (st != KC_OK)
        return st;
    kc_chain_add_const(chain, KC_CODE_RX, row->alpha);
    kc_chain_add_const(chain, KC_CODE_TX, row->a);
    add_dh_joint(chain, row);
    return kc_chain_add_frame(chain);
}

static kc_status check_rigid(const kc_pose *p)
{
    if (p == NULL || !kc_pose_isfinite(p) || !(kc_mat3_rotation_error(&p->R) <= KC_TOL_ORTHONORMAL))
        return KC_E_ARG;
    return KC_OK;
}

kc_status kc_chain_set_base(kc_chain *chain, const kc_pose *base)
{
    if (chain == NULL || check_rigid(base) != KC_OK)
        return KC_E_ARG;
    chain->base = *base;
    return KC_OK;
}

kc_status kc_chain_set_tool(kc_chain *chain, const kc_pose *tool)
{
    if (chain == NULL || check_rigid(tool) != KC_OK)
        return KC_E_ARG;
    chain->tool = *tool;
    return KC_OK;
}

kc_status kc_chain_add_volume(kc_chain *chain, int frame, const kc_shape *shape)
{
    if (chain == NULL || shape == NULL || frame < 0 || frame >= chain->n_frames || kc_shape_check(shape, 0) != KC_OK)
        return KC_E_ARG;
    if (chain->n_volumes >= KC_MAX_VOLUMES)
        return KC_E_CAPACITY;
    chain->volumes[chain->n_volumes].frame = frame;
    chain->volumes[chain->n_volumes].shape = *shape;
    chain->n_volumes++;
    return KC_OK;
}

kc_status kc_chain_set_limits(kc_chain *chain, int j, const kc_joint_limits *limits)
{
    if (chain == NULL || j < 0 || j >= chain->n_joints || kc_chain_check_limits(limits) != KC_OK)
        return KC_E_ARG;
    chain->joints[j].limits = *limits;
    return KC_OK;
}

kc_status kc_chain_check(const kc_chain *chain)
{
    if (chain == NULL || chain->n_joints < 1 || chain->n_joints > KC_MAX_JOINTS ||
        chain->n_elements > KC_MAX_ELEMENTS || chain->n_frames > KC_MAX_FRAMES)
        return KC_E_ARG;
    for (int j = 0; j < chain->n_joints; j++)
        if (!kc_isfinite(chain->joints[j].offset) || kc_chain_check_limits(&chain->joints[j].limits) != KC_OK)
            return KC_E_ARG;
    int seen[KC_MAX_JOINTS] = {0};
    for (int e = 0; e < chain->n_elements; e++) {
        const kc_element *el = &chain->elements[e];
        if (is_joint_code(el->code)) {
            if (el->joint < 0 || el->joint >= chain->n_joints)
                return KC_E_ARG;
            seen[el->joint]++;
        } else if (!is_const_code(el->code) || !kc_isfinite(el->value)) {
            return KC_E_ARG;
        }
    }
    for (int j = 0; j < chain->n_joints; j++)
        if (seen[j] != 1)
            return KC_E_ARG; /* every joint drives exactly one transform */
    for (int f = 0; f < chain->n_frames; f++)
        if (chain->frame_end[f] > chain->n_elements || (f > 0 && chain->frame_end[f] < chain->frame_end[f - 1]))
            return KC_E_ARG;
    if (check_rigid(&chain->base) != KC_OK || check_rigid(&chain->tool) != KC_OK)
        return KC_E_ARG;
    if (chain->n_volumes < 0 || chain->n_volumes > KC_MAX_VOLUMES)
        return KC_E_ARG;
    for (int v = 0; v < chain->n_volumes; v++)
        if (chain->volumes[v].frame < 0 || chain->volumes[v].frame >= chain->n_frames ||
            kc_shape_check(&chain->volumes[v].shape, 0) != KC_OK)
            return KC_E_ARG;
    return KC_OK;
}

kc_status kc_chain_check_q(const kc_chain *chain, const kc_real *q, int *bad_joint)
{
    if (chain == NULL || q == NULL)
        return KC_E_ARG;
    for (int j = 0; j < chain->n_joints; j++) {
        kc_status st = KC_OK;
        if (!kc_isfinite(q[j]))
            st = KC_E_ARG;
        else if (q[j] < chain->joints[j].limits.q_min || q[j] > chain->joints[j].limits.q_max)
            st = KC_E_LIMIT;
        if (st != KC_OK) {
            if (bad_joint != NULL)
                *bad_joint = j;
            return st;
        }
    }
    return KC_OK;
}

/* ---- built-in models ---- */

static kc_joint_limits limits_of(kc_real q_min, kc_real q_max, kc_real qd, kc_real qdd, kc_real qddd)
{
    kc_joint_limits l = {q_min, q_max, qd, qdd, qddd};
    return l;
}

static kc_status build_rrr3(kc_chain *c, const kc_real len[3])
{
    /* Seed 000: a = (0, l2, l3), d = (l1, 0, 0), alpha = (pi/2, 0, 0). The
     * seed gives no limits: +-pi and moderate rates are assumed. */
    kc_joint_limits l = limits_of(-KC_PI, KC_PI, KC_R(2.0), KC_R(8.0), KC_R(80.0));
    kc_dh_row rows[3] = {
        {KC_JOINT_REVOLUTE, KC_R(0.0), KC_PI_2, len[0], KC_R(0.0), l},
        {KC_JOINT_REVOLUTE, len[1], KC_R(0.0), KC_R(0.0), KC_R(0.0), l},
        {KC_JOINT_REVOLUTE, len[2], KC_R(0.0), KC_R(0.0), KC_R(0.0), l},
    };
    kc_status st = KC_OK;
    for (int i = 0; i < 3 && st == KC_OK; i++)
        st = kc_chain_add_dh(c, &rows[i]);
    return st;
}

static kc_status build_planar2(kc_chain *c, const kc_real len[2])
{
    /* Lab 4 gives speeds up to 80 deg/s and accelerations up to 800 deg/s^2
     * but no link lengths (only a figure): lengths are parameters. */
    kc_joint_limits l = limits_of(-KC_PI, KC_PI, KC_R(80.0) * KC_DEG, KC_R(800.0) * KC_DEG,
                                  KC_R(8000.0) * KC_DEG);
    kc_status st = KC_OK;
    for (int i = 0; i < 2 && st == KC_OK; i++) {
        kc_dh_row row = {KC_JOINT_REVOLUTE, len[i], KC_R(0.0), KC_R(0.0), KC_R(0.0), l};
        st = kc_chain_add_dh(c, &row);
    }
    return st;
}

static kc_status build_puma560(kc_chain *c)
{
    /* vectors/fk.json (rtb's Puma560): standard DH and position limits. Rate
     * limits are not in the reference data; these are assumed, below the
     * arm's published maximum speeds. */
    static const kc_real a[6] = {KC_R(0.0), KC_R(0.4318), KC_R(0.0203), KC_R(0.0), KC_R(0.0), KC_R(0.0)};
    static const kc_real d[6] = {KC_R(0.67183), KC_R(0.0), KC_R(0.15005), KC_R(0.4318), KC_R(0.0), KC_R(0.0)};
    static const kc_real alpha[6] = {KC_R(1.5707963267948966), KC_R(0.0), KC_R(-1.5707963267948966),
                                     KC_R(1.5707963267948966), KC_R(-1.5707963267948966), KC_R(0.0)};
    static const kc_real qlim[6][2] = {{KC_R(-2.792526803190927), KC_R(2.792526803190927)},   {KC_R(-0.7853981633974483), KC_R(3.9269908169872414)},
                                       {KC_R(-3.9269908169872414), KC_R(0.7853981633974483)}, {KC_R(-1.9198621771937625), KC_R(2.9670597283903604)},
                                       {KC_R(-1.7453292519943295), KC_R(1.7453292519943295)}, {KC_R(-4.642575810304916), KC_R(4.642575810304916)}};
    static const kc_real qd[6] = {KC_R(2.0), KC_R(2.0), KC_R(2.0), KC_R(4.0), KC_R(4.0), KC_R(4.0)};
    static const kc_real qdd[6] = {KC_R(5.0), KC_R(5.0), KC_R(5.0), KC_R(10.0), KC_R(10.0), KC_R(10.0)};
    kc_status st = KC_OK;
    for (int i = 0; i < 6 && st == KC_OK; i++) {
        kc_dh_row row = {KC_JOINT_REVOLUTE, a[i], alpha[i], d[i], KC_R(0.0),
                         limits_of(qlim[i][0], qlim[i][1], qd[i], qdd[i], KC_R(10.0) * qdd[i])};
        st = kc_chain_add_dh(c, &row);
    }
    return st;
}

static kc_status build_panda(kc_chain *c)
{
    /* vectors/fk.json (rtb's Panda): modified DH, flange then tool Rz(-pi/4)
     * Tz(0.103). Rate limits from Franka's datasheet. */
    static const kc_real a_prev[7] = {KC_R(0.0), KC_R(0.0), KC_R(0.0), KC_R(0.0825), KC_R(-0.0825), KC_R(0.0), KC_R(0.088)};
    static const kc_real alpha_prev[7] = {KC_R(0.0), KC_R(-1.5707963267948966), KC_R(1.5707963267948966), KC_R(1.5707963267948966),
                                          KC_R(-1.5707963267948966), KC_R(1.5707963267948966), KC_R(1.5707963267948966)};
    static const kc_real d[7] = {KC_R(0.333), KC_R(0.0), KC_R(0.316), KC_R(0.0), KC_R(0.384), KC_R(0.0), KC_R(0.107)};
    static const kc_real qlim[7][2] = {{KC_R(-2.8973), KC_R(2.8973)}, {KC_R(-1.7628), KC_R(1.7628)}, {KC_R(-2.8973), KC_R(2.8973)}, {KC_R(-3.0718), KC_R(-0.0698)},
                                       {KC_R(-2.8973), KC_R(2.8973)}, {KC_R(-0.0175), KC_R(3.7525)}, {KC_R(-2.8973), KC_R(2.8973)}};
    static const kc_real qd[7] = {KC_R(2.175), KC_R(2.175), KC_R(2.175), KC_R(2.175), KC_R(2.61), KC_R(2.61), KC_R(2.61)};
    static const kc_real qdd[7] = {KC_R(15.0), KC_R(7.5), KC_R(10.0), KC_R(12.5), KC_R(15.0), KC_R(20.0), KC_R(20.0)};
    static const kc_real qddd[7] = {KC_R(7500.0), KC_R(3750.0), KC_R(5000.0), KC_R(6250.0), KC_R(7500.0), KC_R(10000.0), KC_R(10000.0)};
    kc_status st = KC_OK;
    for (int i = 0; i < 7 && st == KC_OK; i++) {
        kc_dh_row row = {KC_JOINT_REVOLUTE, a_prev[i], alpha_prev[i], d[i], KC_R(0.0),
                         limits_of(qlim[i][0], qlim[i][1], qd[i], qdd[i], qddd[i])};
        st = kc_chain_add_mdh(c, &row);
    }
    if (st != KC_OK)
        return st;
    kc_pose tool;
    kc_mat3_rot(KC_AXIS_Z, -KC_PI / KC_R(4.0), &tool.R);
    tool.t = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(0.103));
    return kc_chain_set_tool(c, &tool);
}

/* One seed 003 coded transform with the frame it ends, then, if len != 0,
 * the link length as a constant translation along the new frame's z (an
 * assumption: the scan's length column is illegible, see the model files). */
static kc_status add_coded(kc_chain *c, int code, kc_real len, const kc_joint_limits *l)
{
    kc_status st;
    if (len != KC_R(0.0)) {
        st = kc_chain_add_const(c, KC_CODE_TZ, len);
        if (st != KC_OK)
            return st;
    }
    if (is_joint_code(code))
        return kc_chain_add_joint(c, (kc_code)code, KC_R(0.0), l);
    st = kc_chain_add_const(c, (kc_code)code, KC_R(0.0));
    return st == KC_OK ? kc_chain_add_frame(c) : st;
}

static kc_status build_coded(kc_chain *c, const int *codes, const kc_real *lens, int n)
{
    kc_joint_limits l = limits_of(-KC_PI, KC_PI, KC_R(1.5), KC_R(6.0), KC_R(60.0));
    kc_status st = KC_OK;
    for (int i = 0; i < n && st == KC_OK; i++)
        st = add_coded(c, codes[i], lens[i], &l);
    return st;
}

static kc_status build_rb211(kc_chain *c)
{
    /* Table 5, RB-211: n_m = 7 frames, n = 6 joints, codes 3 1 1 3 2 9 3.
     * Lengths l1..l4 are symbolic in the scan: assumed values (m), each a
     * translation along z before the coded rotation. The constant code 9
     * carries the table's fictitious 0 angle. */
    static const int codes[7] = {3, 1, 1, 3, 2, 9, 3};
    static const kc_real lens[7] = {KC_R(0.0), KC_R(0.5), KC_R(0.4), KC_R(0.3), KC_R(0.1), KC_R(0.0), KC_R(0.08)};
    return build_coded(c, codes, lens, 7);
}

static kc_status build_rm01(kc_chain *c)
{
    /* Table 5, RM-01 (a PUMA-like arm): n_m = 9 frames, n = 6 joints, codes
     * 9 3 1 7 1 9 3 1 2. Constant angles as read (0, 0 and 0 after the
     * fictitious entries), lengths assumed (m) as for RB-211. */
    static const int codes[9] = {9, 3, 1, 7, 1, 9, 3, 1, 2};
    static const kc_real lens[9] = {KC_R(0.0), KC_R(0.66), KC_R(0.0), KC_R(0.0), KC_R(0.43), KC_R(0.0), KC_R(0.0), KC_R(0.43), KC_R(0.06)};
    return build_coded(c, codes, lens, 9);
}

/* ---- built-in link volumes ----
 *
 * Capsules around each link's segments, written in the frame that carries
 * the segment rigidly. Standard DH (A_i = Rz(q) Tz(d) Tx(a) Rx(alpha)):
 * frame i-1's origin is, in frame i, (-a, -d sin(alpha), -d cos(alpha)), and
 * the corner of the link's L (after Tz(d)) is (-a, 0, 0), whatever q.
 * Modified DH (A_i = Rx(alpha) Tx(a) Rz(q) Tz(d)): the offset a is the
 * segment from 0 to (a, 0, 0) in frame i-1, the offset d the segment from
 * (0, 0, -d) to 0 in frame i. Coded chains (Tz(len) then the code): the
 * segment from 0 to (0, 0, len) in the frame before. Columns standing on
 * the base start 0.15 m above it, so a table top under the base is clear.
 * Radii are assumptions of the links' thickness. */

/* A segment volume (capsule or cylinder) of a built-in arm: its frame,
 * kind, end points (m, in the frame) and radius (m). */
typedef struct seg_row {
    int frame, kind;
    kc_vec3 p0, p1;
    kc_real r;
} seg_row;

/* A capsule row of literals. */
#define CAPS(frame, x0, y0, z0, x1, y1, z1, r)                                                                \
    {                                                                                                        \
        frame, KC_SHAPE_CAPSULE, {{KC_R(x0), KC_R(y0), KC_R(z0)}}, {{KC_R(x1), KC_R(y1), KC_R(z1)}}, KC_R(r) \
    }

static kc_status add_rows(kc_chain *c, const seg_row *rows, int n)
{
    kc_status st = KC_OK;
    for (int i = 0; i < n && st == KC_OK; i++) {
        kc_shape s;
        st = kc_shape_segment(rows[i].kind, &rows[i].p0, &rows[i].p1, rows[i].r, &s);
        if (st == KC_OK)
            st = kc_chain_add_volume(c, rows[i].frame, &s);
    }
    return st;
}

static kc_status volumes_rrr3(kc_chain *c, const kc_real len[3])
{
    kc_real z = KC_R(0.0), col = kc_max(len[0] - KC_R(0.15), KC_R(0.5) * len[0]);
    seg_row rows[3] = {
        {0, KC_SHAPE_CAPSULE, {{z, -col, z}}, {{z, z, z}}, KC_R(0.05)},
        {1, KC_SHAPE_CAPSULE, {{-len[1], z, z}}, {{z, z, z}}, KC_R(0.04)},
        {2, KC_SHAPE_CAPSULE, {{-len[2], z, z}}, {{z, z, z}}, KC_R(0.035)},
    };
    return add_rows(c, rows, 3);
}

static kc_status volumes_planar2(kc_chain *c, const kc_real len[2])
{
    kc_real z = KC_R(0.0);
    seg_row rows[2] = {
        {0, KC_SHAPE_CAPSULE, {{-len[0], z, z}}, {{z, z, z}}, KC_R(0.04)},
        {1, KC_SHAPE_CAPSULE, {{-len[1], z, z}}, {{z, z, z}}, KC_R(0.03)},
    };
    return add_rows(c, rows, 2);
}

static kc_status volumes_puma560(kc_chain *c)
{
    /* column (d1 = 0.672, alpha1 = pi/2), upper arm (a2), the elbow's
     * d3/a3 offset, forearm (d4), wrist and flange */
    static const seg_row rows[5] = {
        CAPS(0, 0.0, -0.52, 0.0, 0.0, 0.0, 0.0, 0.10),
        CAPS(1, -0.4318, 0.0, 0.0, 0.0, 0.0, 0.0, 0.08),
        CAPS(2, -0.0203, 0.15005, 0.0, -0.0203, 0.0, 0.0, 0.06),
        CAPS(3, 0.0, -0.4318, 0.0, 0.0, 0.0, 0.0, 0.05),
        CAPS(5, 0.0, 0.0, -0.03, 0.0, 0.0, 0.06, 0.04),
    };
    return add_rows(c, rows, 5);
}

static kc_status volumes_panda(kc_chain *c)
{
    /* link 1 (d1 = 0.333), upper arm (d3 = 0.316), the elbow's a = +-0.0825
     * offsets, forearm (d5 = 0.384), the wrist's a = 0.088, flange (d7 =
     * 0.107), then the hand: a box 0.2 m wide across the fingers, turned
     * like the tool (Rz(-pi/4)). */
    static const seg_row rows[7] = {
        CAPS(0, 0.0, 0.0, -0.19, 0.0, 0.0, 0.0, 0.08),
        CAPS(2, 0.0, 0.0, -0.316, 0.0, 0.0, 0.0, 0.07),
        CAPS(2, 0.0, 0.0, 0.0, 0.0825, 0.0, 0.0, 0.07),
        CAPS(3, 0.0, 0.0, 0.0, -0.0825, 0.0, 0.0, 0.07),
        CAPS(4, 0.0, 0.0, -0.384, 0.0, 0.0, 0.0, 0.06),
        CAPS(5, 0.0, 0.0, 0.0, 0.088, 0.0, 0.0, 0.06),
        CAPS(6, 0.0, 0.0, -0.107, 0.0, 0.0, 0.0, 0.05),
    };
    kc_status st = add_rows(c, rows, 7);
    if (st == KC_OK) {
        kc_shape hand;
        hand.kind = KC_SHAPE_BOX;
        kc_mat3_rot(KC_AXIS_Z, -KC_PI / KC_R(4.0), &hand.pose.R);
        hand.pose.t = kc_vec3_make(KC_R(0.0), KC_R(0.0), KC_R(0.05));
        hand.dim[0] = KC_R(0.03);
        hand.dim[1] = KC_R(0.10);
        hand.dim[2] = KC_R(0.04);
        hand.dim[3] = hand.dim[4] = KC_R(0.0);
        st = kc_chain_add_volume(c, 6, &hand);
    }
    return st;
}

static kc_status volumes_rb211(kc_chain *c)
{
    /* Seed 003 on RB-211: a cylinder of revolution in O_3 and a truncated
     * pyramid in O_4 (frames 2 and 3 here), capsules elsewhere. */
    static const seg_row rows[4] = {
        CAPS(0, 0.0, 0.0, 0.15, 0.0, 0.0, 0.5, 0.08),
        CAPS(1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.4, 0.06),
        {2, KC_SHAPE_CYLINDER, {{KC_R(0.0), KC_R(0.0), KC_R(0.0)}}, {{KC_R(0.0), KC_R(0.0), KC_R(0.3)}}, KC_R(0.05)},
        CAPS(5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.08, 0.03),
    };
    kc_status st = add_rows(c, rows, 3); /* the frustum comes fourth */
    if (st == KC_OK) {
        kc_shape f;
        f.kind = KC_SHAPE_FRUSTUM;
        kc_pose_identity(&f.pose);
        f.pose.t.v[2] = KC_R(0.05);
        f.dim[0] = f.dim[1] = KC_R(0.05);
        f.dim[2] = f.dim[3] = KC_R(0.03);
        f.dim[4] = KC_R(0.05);
        st = kc_chain_add_volume(c, 3, &f);
    }
    return st == KC_OK ? add_rows(c, rows + 3, 1) : st;
}

static kc_status volumes_rm01(kc_chain *c)
{
    static const seg_row rows[4] = {
        CAPS(1, 0.0, 0.0, -0.51, 0.0, 0.0, 0.0, 0.09),
        CAPS(3, 0.0, 0.0, 0.0, 0.0, 0.0, 0.43, 0.07),
        CAPS(6, 0.0, 0.0, 0.0, 0.0, 0.0, 0.43, 0.05),
        CAPS(7, 0.0, 0.0, 0.0, 0.0, 0.0, 0.06, 0.04),
    };
    return add_rows(c, rows, 4);
}

#undef CAPS

static const char *const model_names[KC_MODEL_COUNT] = {"rrr3", "planar2", "puma560", "panda", "rb211", "rm01"};

const char *kc_model_name(kc_model model)
{
    return (unsigned)model < (unsigned)KC_MODEL_COUNT ? model_names[model] : NULL;
}

int kc_model_from_name(const char *name)
{
    if (name == NULL)
        return KC_E_ARG;
    for (int m = 0; m < KC_MODEL_COUNT; m++) {
        const char *a = model_names[m], *b = name;
        while (*a != '\0' && *a == *b) {
            a++;
            b++;
        }
        if (*a == '\0' && *b == '\0')
            return m;
    }
    return KC_E_ARG;
}

kc_status kc_chain_init_model(kc_chain *chain, kc_model model, const kc_model_params *params)
{
    kc_real len[4] = {KC_R(0.4), KC_R(0.3), KC_R(0.25), KC_R(0.0)};
    kc_chain tmp;
    kc_status st;
    if (chain == NULL || (unsigned)model >= (unsigned)KC_MODEL_COUNT)
        return KC_E_ARG;
    if (model == KC_MODEL_PLANAR2) {
        len[0] = KC_R(0.5);
        len[1] = KC_R(0.4);
    }
    if (params != NULL) {
        for (int i = 0; i < 4; i++) {
            if (!kc_isfinite(params->len[i]))
                return KC_E_ARG;
            if (params->len[i] > KC_R(0.0))
                len[i] = params->len[i];
        }
    }
    kc_chain_init(&tmp);
    switch (model) {
    case KC_MODEL_RRR3:
        st = build_rrr3(&tmp, len);
        if (st == KC_OK)
            st = volumes_rrr3(&tmp, len);
        break;
    case KC_MODEL_PLANAR2:
        st = build_planar2(&tmp, len);
        if (st == KC_OK)
            st = volumes_planar2(&tmp, len);
        break;
    case KC_MODEL_PUMA560:
        st = build_puma560(&tmp);
        if (st == KC_OK)
            st = volumes_puma560(&tmp);
        break;
    case KC_MODEL_PANDA:
        st = build_panda(&tmp);
        if (st == KC_OK)
            st = volumes_panda(&tmp);
        break;
    case KC_MODEL_RB211:
        st = build_rb211(&tmp);
        if (st == KC_OK)
            st = volumes_rb211(&tmp);
        break;
    case KC_MODEL_RM01:
        st = build_rm01(&tmp);
        if (st == KC_OK)
            st = volumes_rm01(&tmp);
        break;
    default: st = KC_E_ARG; break;
    }
    if (st == KC_OK)
        st = kc_chain_check(&tmp);
    if (st == KC_OK)
        *chain = tmp;
    return st;
}
