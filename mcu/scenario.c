/* SPDX-License-Identifier: BSD-3-Clause */
/* scenario.c - the shared goals of the bare-metal programs (scenario.h).
 * Moves of 0.1-0.2 m or 0.2 rad, all well inside the PUMA 560's reach. */
#include "scenario.h"

#include <string.h>

const kc_goal_kind scn_kinds[SCN_KINDS] = {KC_GOAL_JOINT, KC_GOAL_LINE,      KC_GOAL_ARC,
                                           KC_GOAL_PATH,  KC_GOAL_PATH_CART, KC_GOAL_SERVO};
const char *const scn_kind_names[SCN_KINDS] = {"joint", "line", "arc", "path", "path_cart", "servo"};
const kc_real scn_q0[6] = {KC_R(0.1), KC_R(0.8), KC_R(-2.4), KC_R(0.1), KC_R(0.6), KC_R(0.2)};

/* Knots of the paths: a joint path adds joint_off[i] to every joint, a
 * Cartesian path cart_off[i] to the tool position. */
static const kc_real joint_off[3] = {KC_R(0.1), KC_R(0.25), KC_R(0.15)};
static const kc_real cart_off[2][3] = {{KC_R(0.0), KC_R(0.1), KC_R(0.0)}, {KC_R(0.05), KC_R(0.2), KC_R(0.0)}};

void scn_goal(kc_goal *g, kc_goal_kind kind, int64_t id, const kc_pose *here, int k)
{
    memset(g, 0, sizeof *g);
    g->id = id;
    g->kind = kind;
    g->vel_scale = g->acc_scale = KC_R(1.0);
    g->pose = *here;
    switch (kind) {
    case KC_GOAL_JOINT:
        for (int j = 0; j < 6; j++)
            g->q[j] = scn_q0[j] + KC_R(0.2);
        break;
    case KC_GOAL_LINE:
        g->orient = KC_INTERP_SLERP;
        g->pose.t.v[1] += KC_R(0.2);
        break;
    case KC_GOAL_ARC:
        g->via = here->t;
        g->via.v[0] += KC_R(0.05);
        g->via.v[1] += KC_R(0.1);
        g->pose.t.v[1] += KC_R(0.2);
        break;
    case KC_GOAL_PATH:
    case KC_GOAL_PATH_CART: {
        g->method = KC_PATH_SPLINE;
        g->n_points = kind == KC_GOAL_PATH ? 3 : 2;
        kc_quat r;
        kc_quat_from_mat3(&here->R, &r);
        for (int i = 0; i < g->n_points; i++) {
            if (kind == KC_GOAL_PATH) {
                for (int j = 0; j < 6; j++)
                    g->points[i][j] = scn_q0[j] + joint_off[i];
            } else {
                for (int c = 0; c < 3; c++)
                    g->points[i][c] = here->t.v[c] + cart_off[i][c];
                g->points[i][3] = r.w;
                g->points[i][4] = r.x;
                g->points[i][5] = r.y;
                g->points[i][6] = r.z;
            }
        }
        break;
    }
    case KC_GOAL_SERVO:
        g->pose.t.v[1] += KC_R(0.0001) * (kc_real)k;
        break;
    }
}
