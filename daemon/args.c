/* SPDX-License-Identifier: BSD-3-Clause */
/* args.c - kinctld's command line (config_internal.h): getopt_long over
 * the options --help lists; applied over the file in config.c. */
#include "kinctl/version.h"
#include "config_internal.h"

#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>

static void usage(FILE *out)
{
    fprintf(out,
            "Usage: kinctld [options]\n"
            "\n"
            "kinctl's motion controller daemon: takes goals over LCM, publishes a\n"
            "joint setpoint every cycle (simulated arm). With no options: the\n"
            "built-in puma560 at 1 kHz on $LCM_DEFAULT_URL or " KD_DEFAULT_URL ".\n"
            "\n"
            "Options (they override the configuration file):\n"
            "  -c, --config FILE     robot description and/or controller section\n"
            "                        (libconfig; see daemon/README.md)\n"
            "  -m, --model NAME      built-in arm: rrr3 planar2 puma560 panda rb211 rm01\n"
            "  -p, --period-us N     cycle period in us (%d .. %d; default 1000)\n"
            "  -P, --prefix TEXT     channel prefix (default \"" KD_DEFAULT_PREFIX "\")\n"
            "  -u, --lcm-url URL     LCM URL (default $LCM_DEFAULT_URL, else " KD_DEFAULT_URL ")\n"
            "      --rt              SCHED_FIFO, mlockall and CPU affinity (default)\n"
            "      --no-rt           none of them (tests, sanitizers, laptops)\n"
            "      --check           read and check the configuration, print it, exit\n"
            "  -h, --help            this text\n"
            "  -V, --version         print kinctld's version and exit\n"
            "\n"
            "Channels: <prefix>GOAL_JOINT GOAL_LINE GOAL_ARC GOAL_PATH GOAL_SERVO COMMAND\n"
            "(in), <prefix>SETPOINT STATUS STATS (out). Setpoints to drives over SocketCAN\n"
            "(CiA 402 cyclic synchronous position): the controller.can section.\n"
            "\n"
            "Example:\n"
            "  kinctld --model panda --period-us 500 --lcm-url 'udpm://239.255.76.67:7667?ttl=0' --no-rt\n"
            "  kinctld --config /etc/kinctl/puma560.cfg\n"
            "\n"
            "Exit status: 0 after SIGINT/SIGTERM (arm stopped), 1 on a run-time\n"
            "failure, 2 on a bad configuration or command line.\n",
            KD_PERIOD_US_MIN, KD_PERIOD_US_MAX);
}

/* Parses a whole decimal integer. */
static int parse_long(const char *s, long *out)
{
    char *end;
    long v;
    errno = 0;
    v = strtol(s, &end, 10);
    if (errno != 0 || end == s || *end != '\0')
        return -1;
    *out = v;
    return 0;
}

kd_config_result kd_args_parse(kd_args *a, int argc, char **argv)
{
    enum { OPT_RT = 256, OPT_NO_RT, OPT_CHECK };
    static const struct option opts[] = {
        {"config", required_argument, NULL, 'c'},  {"model", required_argument, NULL, 'm'},
        {"period-us", required_argument, NULL, 'p'}, {"prefix", required_argument, NULL, 'P'},
        {"lcm-url", required_argument, NULL, 'u'}, {"rt", no_argument, NULL, OPT_RT},
        {"no-rt", no_argument, NULL, OPT_NO_RT},   {"check", no_argument, NULL, OPT_CHECK},
        {"help", no_argument, NULL, 'h'},          {"version", no_argument, NULL, 'V'},
        {NULL, 0, NULL, 0}};
    int opt;

    a->config_path = a->model = a->prefix = a->url = NULL;
    a->period_us = -1;
    a->rt = -1;
    a->check = 0;
    opterr = 0;
    optind = 1;
    while ((opt = getopt_long(argc, argv, ":c:m:p:P:u:hV", opts, NULL)) != -1) {
        switch (opt) {
        case 'c': a->config_path = optarg; break;
        case 'm': a->model = optarg; break;
        case 'p':
            if (parse_long(optarg, &a->period_us) != 0 || a->period_us < KD_PERIOD_US_MIN ||
                a->period_us > KD_PERIOD_US_MAX) {
                kd_problem("--period-us \"%s\": expected a whole number of us in %d .. %d", optarg, KD_PERIOD_US_MIN,
                        KD_PERIOD_US_MAX);
                return KD_CONFIG_ERROR;
            }
            break;
        case 'P': a->prefix = optarg; break;
        case 'u': a->url = optarg; break;
        case OPT_RT: a->rt = 1; break;
        case OPT_NO_RT: a->rt = 0; break;
        case OPT_CHECK: a->check = 1; break;
        case 'h': usage(stdout); return KD_CONFIG_EXIT;
        case 'V': printf("kinctld %s\n", KC_VERSION); return KD_CONFIG_EXIT;
        case ':':
            kd_problem("%s needs a value (see --help)", argv[optind - 1]);
            return KD_CONFIG_ERROR;
        default:
            kd_problem("unknown option \"%s\" (see --help)", argv[optind - 1]);
            return KD_CONFIG_ERROR;
        }
    }
    if (optind < argc) {
        kd_problem("unexpected argument \"%s\" (see --help)", argv[optind]);
        return KD_CONFIG_ERROR;
    }
    if (a->model != NULL && kc_model_from_name(a->model) < 0) {
        kd_problem("--model \"%s\": no such built-in model (rrr3, planar2, puma560, panda, rb211, rm01)", a->model);
        return KD_CONFIG_ERROR;
    }
    return KD_CONFIG_RUN;
}
