/* SPDX-License-Identifier: BSD-3-Clause */
/* fuzz_desc.c - the robot description reader (core/desc) on arbitrary text.
 * Invariants: no crash or sanitizer report; a refusal names a line and a
 * problem; an accepted chain passes kc_chain_check and its forward
 * kinematics inside the limits is finite. Inputs with @include are skipped:
 * they read other files, which is not the text under test (and a fuzzer
 * would find /dev/zero). */
#include <string.h>

#include "fuzz_check.h"
#include "kinctl/desc.h"
#include "kinctl/fk.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int has_include(const char *text)
{
    for (const char *p = text; (p = strchr(p, '@')) != NULL; p++)
        if (strncmp(p + 1, "include", 7) == 0)
            return 1;
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static char text[1 << 16];
    static kc_chain chain;
    kc_desc_info info;
    kc_desc_error err;
    if (size >= sizeof text)
        return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    if (has_include(text))
        return 0;
    memset(&err, 0, sizeof err);
    kc_status st = kc_desc_load_string(text, "fuzz.cfg", &chain, &info, &err);
    if (st != KC_OK) {
        FUZZ_CHECK(st < 0, "status %d", (int)st);
        FUZZ_CHECK(err.text[0] != '\0' && memchr(err.text, '\0', sizeof err.text) != NULL, "no message");
        return 0;
    }
    FUZZ_CHECK(kc_chain_check(&chain) == KC_OK, "accepted chain fails kc_chain_check");
    FUZZ_CHECK(chain.n_joints >= 1 && chain.n_joints <= KC_MAX_JOINTS, "%d joints", chain.n_joints);
    /* Forward kinematics at the middle of every joint's range (or 0 for an
     * unbounded side). */
    kc_real q[KC_MAX_JOINTS];
    for (int j = 0; j < chain.n_joints; j++) {
        const kc_joint_limits *l = &chain.joints[j].limits;
        q[j] = kc_isfinite(l->q_min) && kc_isfinite(l->q_max) ? l->q_min + (l->q_max - l->q_min) * KC_R(0.5)
               : kc_isfinite(l->q_min)                        ? l->q_min
               : kc_isfinite(l->q_max)                        ? l->q_max
                                                              : KC_R(0.0);
    }
    if (kc_chain_check_q(&chain, q, NULL) == KC_OK) {
        kc_pose pose;
        FUZZ_CHECK(kc_fk_eval(&chain, q, &pose) == KC_OK, "fk refused");
        /* Lengths of 1e300 are the file's business; NaN never is. */
        for (int i = 0; i < 3; i++)
            FUZZ_CHECK(pose.t.v[i] == pose.t.v[i], "fk NaN");
    }
    return 0;
}
