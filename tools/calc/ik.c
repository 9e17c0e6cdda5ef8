/* SPDX-License-Identifier: BSD-3-Clause */
/* ik.c - `kinctl-calc ik`: inverse kinematics to a target pose with the
 * solver of kinctl/ik.h (seed 002's dual-quaternion law). */
#include <string.h>

#include "calc.h"

const calc_opt ik_opts[] = {
    CALC_CHAIN_OPTS,
    {"--target", "target", CALC_VALUE, calc_conv_reals, "T",
     "target pose: 16 numbers (row-major 4x4) or x,y,z,qw,qx,qy,qz (m)"},
    {"--q0", "q0", CALC_VALUE, calc_conv_reals, "Q1,Q2,...",
     "start configuration, rad or m (deg with --deg); default: the middle of each joint's range"},
    {"--mask", "mask", CALC_VALUE, calc_conv_string, "TASK",
     "full (default: position and orientation), position, or axis (position and tool z axis)"},
    {"--deg", "deg", CALC_FLAG, NULL, NULL, "revolute joint values (q0 and the answer) in degrees"},
    {NULL, NULL, CALC_FLAG, NULL, NULL, NULL},
};

static int target_of(calc_ctx *ctx, const json_t *req, kc_pose *target)
{
    kc_real v[16];
    int n = 0;
    if (req_reals(ctx, json_object_get(req, "target"), "target", v, 16, &n) != 0)
        return -1;
    if (n == 16) {
        kc_mat4 m;
        for (int i = 0; i < 16; i++)
            m.m[i / 4][i % 4] = v[i];
        if (kc_pose_from_mat4(&m, target) != KC_OK)
            return calc_fail(ctx, "target is not a rigid transform: its 3x3 block must be a rotation "
                                  "(orthonormal, det +1) and its last row 0 0 0 1");
        return 0;
    }
    if (n == 7) {
        kc_quat q = {v[3], v[4], v[5], v[6]}, u;
        kc_real norm = kc_quat_norm(&q);
        if (kc_quat_normalize(&q, &u) != KC_OK)
            return calc_fail(ctx, "target quaternion qw,qx,qy,qz is zero");
        if (kc_fabs(norm - KC_R(1.0)) > KC_R(1e-3))
            calc_warn(ctx, "target quaternion has norm %g; normalised", (double)norm);
        kc_quat_to_mat3(&u, &target->R);
        target->t = kc_vec3_make(v[0], v[1], v[2]);
        return 0;
    }
    return calc_fail(ctx, "target has %d numbers: give 16 (row-major 4x4) or 7 (x,y,z,qw,qx,qy,qz)", n);
}

static int mask_of(calc_ctx *ctx, const json_t *req, kc_ik_mask *mask)
{
    static const char *const names[] = {"full", "position", "axis"};
    const char *name = NULL;
    if (req_string(ctx, req, "mask", 0, &name) != 0)
        return -1;
    if (name == NULL) {
        *mask = KC_IK_MASK_FULL;
        return 0;
    }
    for (int i = 0; i < 3; i++) {
        if (strcmp(name, names[i]) == 0) {
            *mask = (kc_ik_mask)i;
            return 0;
        }
    }
    return calc_fail(ctx, "unknown mask \"%s\": full, position or axis", name);
}

static const char *status_name(kc_status st)
{
    switch (st) {
    case KC_OK: return "converged";
    case KC_E_NOCONVERGE: return "not_converged";
    case KC_E_UNREACHABLE: return "unreachable";
    case KC_E_LIMIT: return "joint_limit";
    case KC_E_SINGULAR: return "singular";
    default: return kc_status_str(st);
    }
}

int run_ik(const json_t *req, calc_ctx *ctx)
{
    kc_chain chain;
    kc_pose target;
    kc_real q0[KC_MAX_JOINTS], q[KC_MAX_JOINTS];
    kc_ik_cfg cfg = kc_ik_cfg_default();
    int deg = 0;
    if (req_bool(ctx, req, "deg", &deg) != 0 || req_model(ctx, req, &chain) != 0 || target_of(ctx, req, &target) != 0 ||
        mask_of(ctx, req, &cfg.mask) != 0)
        return -1;
    if (json_object_get(req, "q0") != NULL) {
        if (req_joints(ctx, req, "q0", &chain, deg, q0) != 0)
            return -1;
    } else {
        for (int j = 0; j < chain.n_joints; j++) {
            const kc_joint_limits *l = &chain.joints[j].limits;
            int bounded = kc_isfinite(l->q_min) && kc_isfinite(l->q_max);
            q0[j] = bounded ? KC_R(0.5) * (l->q_min + l->q_max) : KC_R(0.0);
        }
    }
    kc_ik_result res;
    kc_status st = kc_ik_solve(&chain, &cfg, &target, q0, q, &res);
    if (st == KC_E_ARG)
        return calc_fail(ctx, "ik failed: %s", kc_status_str(st));
    /* Unreachable: nothing was tried, so there is no q and no residual. */
    int tried = st != KC_E_UNREACHABLE;
    for (int j = 0; j < chain.n_joints; j++)
        if (deg && chain.joints[j].type == KC_JOINT_REVOLUTE)
            q[j] /= KC_DEG;
    jw_key(ctx->out, "q");
    if (tried)
        jw_reals(ctx->out, q, chain.n_joints);
    else
        jw_null(ctx->out);
    jw_key(ctx->out, "status");
    jw_str(ctx->out, status_name(st));
    jw_key(ctx->out, "steps");
    jw_real(ctx->out, (kc_real)res.steps);
    jw_key(ctx->out, "restarts");
    jw_real(ctx->out, (kc_real)res.restarts);
    jw_key(ctx->out, "position_error");
    jw_real(ctx->out, tried ? res.pos_err : (kc_real)NAN);
    jw_key(ctx->out, "orientation_error");
    jw_real(ctx->out, tried ? res.rot_err : (kc_real)NAN);
    return 0;
}
