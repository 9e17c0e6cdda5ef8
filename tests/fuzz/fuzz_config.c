/* SPDX-License-Identifier: BSD-3-Clause */
#define _GNU_SOURCE /* memmem */
/* fuzz_config.c - kinctld's configuration reader (daemon/config.c: the
 * controller section and the robot it names) on arbitrary file contents,
 * read as `kinctld --config FILE` would. Invariants: no crash or sanitizer
 * report; a configuration it accepts is one kinctld can run: the chain and
 * controller configuration pass their own checks and the home position is
 * inside the limits. Inputs with @include are skipped (see fuzz_desc.c). */
#include <stdint.h>
#include <string.h>
#include <unistd.h>

#include "config.h"
#include "fuzz_check.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char path[64];

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    snprintf(path, sizeof path, "/tmp/kinctl-fuzz-config-%ld.cfg", (long)getpid());
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static kd_config cfg;
    if (memmem(data, size, "@include", 8) != NULL)
        return 0;
    FILE *f = fopen(path, "wb");
    FUZZ_CHECK(f != NULL, "cannot write %s", path);
    FUZZ_CHECK(fwrite(data, 1, size, f) == size, "short write");
    fclose(f);
    char *argv[] = {"kinctld", "--config", path, NULL};
    kd_config_result r = kd_config_load(&cfg, 3, argv);
    unlink(path);
    FUZZ_CHECK(r == KD_CONFIG_RUN || r == KD_CONFIG_ERROR, "result %d", (int)r);
    if (r != KD_CONFIG_RUN)
        return 0;
    FUZZ_CHECK(kc_chain_check(&cfg.chain) == KC_OK, "accepted chain fails its check");
    FUZZ_CHECK(kc_ctrl_cfg_check(&cfg.ctrl, &cfg.chain) == KC_OK, "accepted controller configuration fails its check");
    FUZZ_CHECK(kc_chain_check_q(&cfg.chain, cfg.home, NULL) == KC_OK, "home outside the limits");
    FUZZ_CHECK(cfg.period_ns > 0 && cfg.queue_size > 0, "period %lld, queue %d", (long long)cfg.period_ns,
               cfg.queue_size);
    FUZZ_CHECK(cfg.lcm_url[0] != '\0', "no LCM URL");
    return 0;
}
