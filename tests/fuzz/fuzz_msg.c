/* SPDX-License-Identifier: BSD-3-Clause */
/* fuzz_msg.c - the daemon's decode-and-validate path for every type a client
 * sends: a raw datagram through kd_msg_decode, then kd_goal_from_msg and
 * kc_ctrl_goal_check for the goals, as lcm_io.c does (its dry run starts
 * with the same check), and the rejection text of the verdict. The first
 * input byte picks the type, the rest is the datagram.
 * Invariants: no crash or sanitizer report; a decoded message re-encodes to
 * the same bytes (decoding lost or invented nothing); a refused datagram
 * leaves the output storage untouched; a refused goal has a reason and a
 * text; a goal that passes every check has only finite numbers. */
#include <math.h>
#include <string.h>

#include "fuzz_check.h"
#include "goal.h"
#include "kinctl/chain.h"
#include "msg.h"
#include "reject.h"

static kd_config cfg; /* the arm only: what a goal's rejection text names */

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    kd_msg_init();
    FUZZ_CHECK(kc_chain_init_model(&cfg.chain, KC_MODEL_PUMA560, NULL) == KC_OK, "puma560");
    return 0;
}

static int goal_finite(const kc_goal *g)
{
    const kc_real *scalars[] = {&g->vel_scale, &g->acc_scale, &g->speed, &g->accel, &g->omega, &g->alpha,
                                &g->blend_time};
    for (size_t i = 0; i < sizeof scalars / sizeof scalars[0]; i++)
        if (!isfinite((double)*scalars[i]))
            return 0;
    for (int j = 0; j < KC_MAX_JOINTS; j++)
        if (!isfinite((double)g->q[j]))
            return 0;
    if (!kc_pose_isfinite(&g->pose) || !kc_vec3_isfinite(&g->via))
        return 0;
    for (int i = 0; i < g->n_points; i++) {
        for (int j = 0; j < KC_MAX_JOINTS; j++)
            if (!isfinite((double)g->points[i][j]))
                return 0;
        if (g->has_times && !isfinite((double)g->times[i]))
            return 0;
    }
    for (int i = 0; i < 6; i++)
        if (!isfinite((double)g->twist[i]))
            return 0;
    return 1;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static kd_msg_any msg, pristine;
    static uint8_t again[KD_MSG_MAX_SIZE];
    char reason[KD_MSG_REASON_SIZE];
    if (size < 1)
        return 0;
    kd_msg_type type = (kd_msg_type)(data[0] % (unsigned)KD_MSG_SETPOINT); /* the client types */
    const uint8_t *dgram = data + 1;
    size_t len = size - 1;

    memset(&msg, 0xA5, sizeof msg);
    memcpy(&pristine, &msg, sizeof msg);
    kd_msg_status st = kd_msg_decode(type, dgram, len, &msg, reason, sizeof reason);
    FUZZ_CHECK(memchr(reason, '\0', sizeof reason) != NULL, "reason not terminated");
    if (st != KD_MSG_OK) {
        FUZZ_CHECK(st < 0, "status %d", (int)st);
        /* Bytes, padding included, on purpose: a refused decode writes none. */
        /* NOLINTNEXTLINE(bugprone-suspicious-memory-comparison,cert-exp42-c,cert-flp37-c) */
        FUZZ_CHECK(memcmp(&msg, &pristine, sizeof msg) == 0, "refused datagram (%s) wrote its output",
                   kd_msg_status_str(st));
        return 0;
    }
    size_t out_len = 0;
    FUZZ_CHECK(kd_msg_encode(type, &msg, again, sizeof again, &out_len) == KD_MSG_OK, "re-encode");
    FUZZ_CHECK(out_len == len && memcmp(again, dgram, len) == 0, "decode/encode not the same bytes (%zu vs %zu)",
               out_len, len);
    if (type == KD_MSG_COMMAND)
        return 0;

    kc_goal goal;
    kc_verdict v;
    kd_reject rej;
    int64_t timeout_ns = -1;
    memset(&rej, 0, sizeof rej);
    if (kd_goal_from_msg(type, &msg, 1.0, &goal, &timeout_ns, &v) != 0 ||
        kc_ctrl_goal_check(&cfg.chain, &goal, &v) != KC_OK) {
        FUZZ_CHECK(v.status < 0 && v.reason != KC_REASON_NONE, "refused without a reason");
        FUZZ_CHECK(v.joint < cfg.chain.n_joints && v.point < KC_PATH_MAX_KNOTS - 1, "a verdict naming joint %d, knot %d",
                   v.joint, v.point);
        kd_reject_verdict(&rej, &cfg, &goal, &v);
        FUZZ_CHECK(rej.code < 0 && rej.text[0] != '\0' && memchr(rej.text, '\0', sizeof rej.text) != NULL,
                   "a refusal without its reason");
        return 0;
    }
    FUZZ_CHECK(v.reason == KC_REASON_NONE, "accepted with reason %d", (int)v.reason);
    FUZZ_CHECK(goal_finite(&goal), "an accepted goal with a non-finite field");
    if (goal.kind == KC_GOAL_SERVO)
        FUZZ_CHECK(timeout_ns > 0 && timeout_ns <= 1000000000, "servo timeout %lld ns", (long long)timeout_ns);
    return 0;
}
