/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * ctrl_hash.c - the determinism program: runs every goal kind of
 * scenario.h through kc_ctrl_step from rest until the controller is idle
 * again, and hashes every tick's output (FNV-1a over the setpoint's q, qd,
 * qdd and tool pose, the state, the active goal and the events). Built for
 * the board and for the host from this one source, against the float core;
 * tests/mcu compares the two printed hashes, which must be equal: the same
 * C, the same IEEE single-precision operations (-ffp-contract=off), the
 * same bits.
 *
 * Then the IK's position task, which no goal uses and which a build for
 * size solves with a kernel of rolled loops (core/src/ik_rolled.c) where
 * the host's is unrolled: online steps and solves on the PUMA 560
 * (redundant: the null-space term too) and the RRR arm, their joint
 * values, rates and residuals hashed too. (The axis task's error goes
 * through atan2f, whose last bit glibc and newlib do not agree on;
 * tests/unit/test_ik_rolled.c compares its kernels bit for bit.)
 *
 * Prints one line per goal kind (ticks, end event, hash so far), one for
 * the IK task, and then "hash <16 hex digits>". Exit status 1 when a goal does not end as it
 * should (completed; the servo aborted by its timeout) within its bound.
 */
#include <stdio.h>
#include <string.h>

#include "kinctl/kinctl.h"
#include "scenario.h"

#define MAX_TICKS 20000

static kc_chain chain;
static kc_ctrl ctrl;
static kc_ctrl_output out;

static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = (const unsigned char *)p;
    for (size_t i = 0; i < n; i++)
        h = (h ^ b[i]) * 1099511628211ULL;
    return h;
}

static uint64_t hash_output(uint64_t h, const kc_ctrl_output *o, int n)
{
    size_t bytes = sizeof(kc_real) * (size_t)n;
    h = fnv(h, o->q, bytes);
    h = fnv(h, o->qd, bytes);
    h = fnv(h, o->qdd, bytes);
    h = fnv(h, &o->pose.R, sizeof o->pose.R);
    h = fnv(h, &o->pose.t, sizeof o->pose.t);
    int32_t words[3] = {(int32_t)o->state, (int32_t)o->goal_id, (int32_t)o->n_events};
    h = fnv(h, words, sizeof words);
    for (int e = 0; e < o->n_events; e++) {
        int32_t ev[3] = {(int32_t)o->events[e].kind, (int32_t)o->events[e].goal_id, (int32_t)o->events[e].reason};
        h = fnv(h, ev, sizeof ev);
    }
    return h;
}

/* IK_TICKS online steps of the position task towards a target from
 * scn_q0, then a solve from scn_q0 to each of three targets (the tool
 * positions of scn_q0 with every joint moved by 0.1, 0.3 and 0.6 rad). */
#define IK_TICKS 200

static uint64_t hash_ik_position(uint64_t h, int *failures)
{
    static const kc_model models[2] = {KC_MODEL_PUMA560, KC_MODEL_RRR3};
    for (int m = 0; m < 2; m++) {
        kc_chain c;
        if (kc_chain_init_model(&c, models[m], NULL) != KC_OK) {
            (*failures)++;
            continue;
        }
        kc_ik_cfg cfg = kc_ik_cfg_default();
        cfg.mask = KC_IK_MASK_POSITION;
        kc_real q[KC_MAX_JOINTS] = {0}, qd[KC_MAX_JOINTS] = {0}, goal[KC_MAX_JOINTS];
        size_t bytes = sizeof(kc_real) * (size_t)c.n_joints;
        memcpy(q, scn_q0, bytes);
        for (int t = 1; t <= 3; t++) {
            kc_pose target;
            kc_ik_result res;
            for (int j = 0; j < c.n_joints; j++)
                goal[j] = scn_q0[j] + (kc_real)(t * t + t) * KC_R(0.05);
            kc_fk_eval(&c, goal, &target);
            for (int i = 0; i < IK_TICKS && t == 1; i++) {
                kc_real qn[KC_MAX_JOINTS], qdn[KC_MAX_JOINTS];
                kc_status st = kc_ik_step(&c, &cfg, &target, NULL, KC_R(0.001), q, qd, qn, qdn, &res);
                if (st < 0 && st != KC_E_LIMIT && st != KC_E_SINGULAR)
                    (*failures)++;
                memcpy(q, qn, bytes);
                memcpy(qd, qdn, bytes);
                h = fnv(h, q, bytes);
                h = fnv(h, qd, bytes);
            }
            kc_real solved[KC_MAX_JOINTS];
            if (kc_ik_solve(&c, &cfg, &target, scn_q0, solved, &res) != KC_OK)
                (*failures)++;
            h = fnv(h, solved, bytes);
            int32_t words[3] = {(int32_t)res.status, (int32_t)res.steps, (int32_t)res.restarts};
            h = fnv(h, words, sizeof words);
            h = fnv(h, &res.pos_err, sizeof res.pos_err);
        }
    }
    return h;
}

/* Halves of a 64-bit value for printf: newlib's strict C99 inttypes.h has
 * no PRIx64. */
static unsigned long hi32(uint64_t x) { return (unsigned long)(x >> 32); }
static unsigned long lo32(uint64_t x) { return (unsigned long)(x & 0xffffffffu); }

int main(void)
{
    uint64_t h = 1469598103934665603ULL;
    int failures = 0;
    if (kc_chain_init_model(&chain, KC_MODEL_PUMA560, NULL) != KC_OK) {
        printf("FAIL: puma560 model\n");
        return 1;
    }
    kc_ctrl_cfg cfg = kc_ctrl_cfg_default();
    for (int s = 0; s < SCN_KINDS; s++) {
        if (kc_ctrl_init(&ctrl, &chain, &cfg, scn_q0) != KC_OK) {
            printf("FAIL: kc_ctrl_init\n");
            return 1;
        }
        kc_pose here;
        kc_fk_eval(&chain, scn_q0, &here);
        int64_t id = 100 + s;
        kc_goal g;
        kc_ctrl_event_kind want = scn_kinds[s] == KC_GOAL_SERVO ? KC_EVENT_ABORTED : KC_EVENT_COMPLETED;
        int ended = 0, ticks = 0;
        for (; ticks < MAX_TICKS && !ended; ticks++) {
            kc_ctrl_input in;
            memset(&in, 0, sizeof in);
            if (ticks == 0 || (scn_kinds[s] == KC_GOAL_SERVO && ticks < SCN_SERVO_TICKS)) {
                scn_goal(&g, scn_kinds[s], id, &here, ticks);
                in.goal = &g;
            }
            kc_ctrl_step(&ctrl, &in, &out);
            h = hash_output(h, &out, chain.n_joints);
            for (int e = 0; e < out.n_events; e++) {
                if (out.events[e].goal_id != id)
                    continue;
                if (out.events[e].kind == want)
                    ended = 1;
                else if (out.events[e].kind != KC_EVENT_ACCEPTED && out.events[e].kind != KC_EVENT_STARTED) {
                    printf("%s: event %d, %s\n", scn_kind_names[s], (int)out.events[e].kind,
                           kc_ctrl_reason_str(out.events[e].reason));
                    ended = -1;
                }
            }
        }
        printf("%-9s %6d ticks  %s  hash %08lx%08lx\n", scn_kind_names[s], ticks,
               ended > 0 ? "ended as expected" : "FAILED", hi32(h), lo32(h));
        if (ended <= 0)
            failures++;
    }
    int ik_failures = 0;
    h = hash_ik_position(h, &ik_failures);
    printf("%-9s %6d steps  %s  hash %08lx%08lx\n", "ik pos", 2 * IK_TICKS, ik_failures ? "FAILED" : "solved",
           hi32(h), lo32(h));
    failures += ik_failures;
    printf("hash %08lx%08lx\n", hi32(h), lo32(h));
    return failures ? 1 : 0;
}
