/* SPDX-License-Identifier: BSD-3-Clause */
/* kinctl-replay - feeds the goals and commands of a recorded LCM event log
 * through kc_ctrl_step offline and checks that every setpoint reproduces
 * bit for bit.
 *
 *   kinctl-replay [--progress] LOG [kinctld options: --config F --model M --period-us N --prefix P]
 *
 * What makes it exact. Every setpoint_t carries the inputs its cycle's step
 * was given (input_goal_id, input_command, input_servo_stale, input_fault,
 * input_seated): the goals that reached the cycle, at the cycle they
 * reached it, after the daemon's I/O thread had dry-run and perhaps
 * rejected others, and what that dry run changed in the goal it handed
 * on (input_goal_share, input_goal_stop_first, input_goal_qu: slowed for
 * its joints' jerk, the motion it replaces stopping first, the hold on
 * its resumes; input_goal_scheduled, input_goal_take_ahead,
 * input_goal_take_state: the tick and state it was judged for, outside
 * which the step refuses it as late). The goal itself is
 * the message in the log with that goal_id (the next one not used yet, in
 * log order) that the daemon took: turned into a kc_goal by the daemon's
 * own kd_goal_from_msg (daemon/goal.c) and passing the core's goal check,
 * with the daemon's own configuration reader (daemon/config.c, the same
 * options as kinctld), so the controller sees the same bits.
 *
 * The replay starts at the log's first setpoint at rest (IDLE, no goal,
 * qd = qdd = 0): the controller is then fully described by its joints, and
 * kc_ctrl_init starts there. Cycle numbers are compared as offsets from that
 * setpoint (the controller counts its own ticks; only differences of ticks
 * enter its arithmetic).
 *
 * Exit status: 0 every setpoint reproduced bit for bit; 1 a setpoint
 * differs (the first one is reported), or the log cannot be followed (a
 * missing setpoint or goal); 2 bad command line, unreadable log, or a log
 * with nothing to replay.
 */
#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <lcm/eventlog.h>

#include "config.h"
#include "goal.h"
#include "kinctl/ctrl.h"
#include "kinctl/se3.h"
#include "kinctl/version.h"
#include "msg.h"

#define PROGRESS_EVERY 2000 /* cycles between progress lines */

static void usage(FILE *f)
{
    fputs("usage: kinctl-replay [--progress] LOG [kinctld options]\n"
          "\n"
          "Feeds the goals and commands recorded in LOG (an LCM event log of kinctl\n"
          "channels, from `kinctl record` or lcm-logger) through the controller step\n"
          "offline and reports whether every setpoint reproduces bit for bit, or the\n"
          "first cycle that differs. The arm, period and channel prefix come from the\n"
          "same options as kinctld's (--config FILE, --model NAME, --period-us N,\n"
          "--prefix P): give the ones the daemon ran with.\n"
          "\n"
          "  --progress   print 'progress DONE TOTAL' lines on stderr\n"
          "  --version    print kinctl-replay's version and exit\n"
          "\n"
          "example:\n"
          "  kinctl-replay run.lcmlog --model panda --period-us 500\n"
          "\n"
          "exit status: 0 bit-exact; 1 a setpoint differs or the log cannot be followed;\n"
          "2 bad command line or log\n",
          f);
}

typedef struct goal_msg {
    kd_msg_type type;
    int64_t id;
    kd_msg_any msg;
    int used;
} goal_msg;

typedef struct recording {
    kinctl_setpoint_t *sp;
    size_t n_sp, cap_sp;
    goal_msg *goals;
    size_t n_goals, cap_goals;
    size_t undecodable; /* datagrams on kinctl input channels that did not decode */
} recording;

static void *grow(void *p, size_t *cap, size_t elem)
{
    size_t c = *cap ? *cap * 2 : 1024;
    void *q = realloc(p, c * elem);
    if (q == NULL) {
        fprintf(stderr, "kinctl-replay: out of memory\n");
        exit(2);
    }
    *cap = c;
    return q;
}

/* Reads the setpoints and the goal messages of prefix's channels. */
static int read_log(const char *path, const char *prefix, recording *r)
{
    char channel[KD_MSG_TYPE_COUNT][KD_PREFIX_MAX + 32];
    lcm_eventlog_t *log;
    lcm_eventlog_event_t *ev;
    int t;
    static const unsigned char magic[4] = {0xed, 0xa1, 0xda, 0x01}; /* every event's sync word */
    unsigned char head[4];
    size_t got;
    FILE *probe = fopen(path, "rb");
    if (probe == NULL) {
        fprintf(stderr, "kinctl-replay: cannot open %s: %s\n", path, strerror(errno));
        return -1;
    }
    got = fread(head, 1, sizeof head, probe);
    fclose(probe);
    if (got != sizeof head || memcmp(head, magic, sizeof magic) != 0) {
        fprintf(stderr, "kinctl-replay: %s is not an LCM event log (written by kinctl record or lcm-logger)\n", path);
        return -1;
    }
    log = lcm_eventlog_create(path, "r");
    if (log == NULL) {
        fprintf(stderr, "kinctl-replay: cannot read %s as an LCM event log\n", path);
        return -1;
    }
    for (t = 0; t < KD_MSG_TYPE_COUNT; t++)
        snprintf(channel[t], sizeof channel[t], "%s%s", prefix, kd_msg_type_info((kd_msg_type)t)->channel);
    while ((ev = lcm_eventlog_read_next_event(log)) != NULL) {
        for (t = 0; t < KD_MSG_TYPE_COUNT; t++)
            if (strcmp(ev->channel, channel[t]) == 0)
                break;
        if (t == KD_MSG_SETPOINT) {
            if (r->n_sp == r->cap_sp)
                r->sp = grow(r->sp, &r->cap_sp, sizeof *r->sp);
            if (kd_msg_decode(KD_MSG_SETPOINT, ev->data, (size_t)ev->datalen, &r->sp[r->n_sp], NULL, 0) == KD_MSG_OK)
                r->n_sp++;
            else
                r->undecodable++;
        } else if (t <= KD_MSG_GOAL_SERVO) {
            goal_msg *g;
            if (r->n_goals == r->cap_goals)
                r->goals = grow(r->goals, &r->cap_goals, sizeof *r->goals);
            g = &r->goals[r->n_goals];
            /* What kd_msg_decode refuses the daemon ignored too. */
            if (kd_msg_decode((kd_msg_type)t, ev->data, (size_t)ev->datalen, &g->msg, NULL, 0) == KD_MSG_OK) {
                g->type = (kd_msg_type)t;
                g->id = kd_msg_goal_id(g->type, ev->data, (size_t)ev->datalen);
                g->used = 0;
                r->n_goals++;
            } else {
                r->undecodable++;
            }
        }
        lcm_eventlog_free_event(ev);
    }
    lcm_eventlog_destroy(log);
    return 0;
}

/* The goal the daemon's cycle took as id: the first message with that id
 * not used yet that the daemon's conversion and the core's goal check
 * accept (one they refused never reached the cycle). 0 with *goal set, or
 * -1. */
static int find_goal(recording *r, const kd_config *cfg, int64_t id, kc_goal *goal)
{
    size_t i;
    for (i = 0; i < r->n_goals; i++) {
        goal_msg *g = &r->goals[i];
        int64_t timeout_ns;
        kc_verdict v;
        if (g->used || g->id != id)
            continue;
        g->used = 1;
        if (kd_goal_from_msg(g->type, &g->msg, cfg->servo_timeout_s, goal, &timeout_ns, &v) == 0 &&
            kc_ctrl_goal_check(&cfg->chain, goal, &v) == KC_OK)
            return 0;
    }
    return -1;
}

/* The goal as the daemon's dry run handed it to the step whose output
 * cycle is `cycle` (the replay's count), from the setpoint's
 * input_goal_share, input_goal_stop_first and input_goal_qu: the motion it
 * replaces stopping first, slowed by kc_goal_slow to its share as kinctld
 * slows it (once, from the goal as asked), its resumes' hold; and from
 * input_goal_scheduled, the tick (input_goal_take_ahead after this one)
 * and state it is to be taken in, so that the step takes or refuses it as
 * kinctld's did. 0, or -1 for a share kc_goal_slow refuses for this goal. */
static int as_handed_on(const kinctl_setpoint_t *sp, const kd_config *cfg, int64_t cycle, kc_goal *goal)
{
    goal->stop_first = sp->input_goal_stop_first != 0;
    if (sp->input_goal_share < 1.0 && kc_goal_slow(goal, &cfg->ctrl, (kc_real)sp->input_goal_share) != KC_OK)
        return -1;
    goal->qu = (kc_real)sp->input_goal_qu;
    if (sp->input_goal_scheduled) {
        goal->take_cycle = cycle + sp->input_goal_take_ahead;
        if (goal->take_cycle == 0) /* 0 would mean "whenever": any other tick is refused alike */
            goal->take_cycle = -1;
        goal->take_state = (uint32_t)sp->input_goal_take_state;
    }
    return 0;
}

static int at_rest(const kinctl_setpoint_t *sp)
{
    int j;
    if (sp->state != KINCTL_SETPOINT_T_IDLE || sp->goal_id != 0)
        return 0;
    for (j = 0; j < sp->n; j++)
        if (sp->qd[j] != 0.0 || sp->qdd[j] != 0.0)
            return 0;
    return 1;
}

/* Compares a field bit for bit; prints the first difference. */
static int same(const char *what, int index, double logged, double replayed, int64_t cycle)
{
    if (memcmp(&logged, &replayed, sizeof logged) == 0)
        return 1;
    printf("DIFFERS at cycle %" PRId64 ": %s[%d] logged %.17g, replayed %.17g (difference %.3g)\n", cycle, what, index,
           logged, replayed, replayed - logged);
    return 0;
}

static int compare(const kinctl_setpoint_t *sp, const kc_ctrl_output *o, int n)
{
    kc_quat q;
    double quat[4];
    int j;
    if (sp->goal_id != o->goal_id) {
        printf("DIFFERS at cycle %" PRId64 ": goal_id logged %" PRId64 ", replayed %" PRId64 "\n", sp->cycle,
               sp->goal_id, o->goal_id);
        return 0;
    }
    if (sp->state != (int8_t)o->state) {
        printf("DIFFERS at cycle %" PRId64 ": state logged %d, replayed %d\n", sp->cycle, sp->state, (int)o->state);
        return 0;
    }
    for (j = 0; j < n; j++)
        if (!same("q", j, sp->q[j], (double)o->q[j], sp->cycle))
            return 0;
    for (j = 0; j < n; j++)
        if (!same("qd", j, sp->qd[j], (double)o->qd[j], sp->cycle))
            return 0;
    for (j = 0; j < n; j++)
        if (!same("qdd", j, sp->qdd[j], (double)o->qdd[j], sp->cycle))
            return 0;
    for (j = 0; j < 3; j++)
        if (!same("position", j, sp->position[j], (double)o->pose.t.v[j], sp->cycle))
            return 0;
    kc_quat_from_mat3(&o->pose.R, &q);
    quat[0] = (double)q.w;
    quat[1] = (double)q.x;
    quat[2] = (double)q.y;
    quat[3] = (double)q.z;
    for (j = 0; j < 4; j++)
        if (!same("orientation", j, sp->orientation[j], quat[j], sp->cycle))
            return 0;
    return 1;
}

static int replay(recording *r, const kd_config *cfg, int progress)
{
    static kc_ctrl ctrl;
    kc_ctrl_output out;
    kc_real q0[KC_MAX_JOINTS];
    size_t start, i;
    int n = cfg->chain.n_joints, j;
    long goals = 0, commands = 0, stale = 0;
    int64_t base;

    for (start = 0; start < r->n_sp && !at_rest(&r->sp[start]); start++) {
    }
    if (start == r->n_sp) {
        fprintf(stderr, "kinctl-replay: no setpoint at rest (IDLE, no goal, qd = qdd = 0) in the log: start "
                        "recording while the arm is idle\n");
        return 2;
    }
    for (j = 0; j < n; j++)
        q0[j] = (kc_real)r->sp[start].q[j];
    if (kc_ctrl_init(&ctrl, &cfg->chain, &cfg->ctrl, q0) != KC_OK) {
        fprintf(stderr, "kinctl-replay: the controller refuses the log's start (joints outside this arm's limits: "
                        "is it the daemon's --config/--model?)\n");
        return 2;
    }
    base = r->sp[start].cycle;
    printf("replay from cycle %" PRId64 " (the first setpoint at rest), %zu setpoints, %zu goal messages\n", base,
           r->n_sp - start, r->n_goals);
    for (i = start + 1; i < r->n_sp; i++) {
        const kinctl_setpoint_t *sp = &r->sp[i];
        kc_ctrl_input in;
        kc_goal goal;
        kc_status st;
        if (sp->cycle != r->sp[i - 1].cycle + 1) {
            printf("INCOMPLETE: the log has no setpoint for cycles %" PRId64 " .. %" PRId64
                   " (lost by the recorder, or dropped by the daemon): bit-exact through cycle %" PRId64
                   " (%zu cycles), not followed further\n",
                   r->sp[i - 1].cycle + 1, sp->cycle - 1, r->sp[i - 1].cycle, i - 1 - start);
            return 1;
        }
        in.goal = NULL;
        if (sp->input_goal_id != 0) {
            if (find_goal(r, cfg, sp->input_goal_id, &goal) != 0) {
                printf("INCOMPLETE: cycle %" PRId64 " took goal %" PRId64 ", which is not in the log: bit-exact "
                       "through cycle %" PRId64 "\n",
                       sp->cycle, sp->input_goal_id, r->sp[i - 1].cycle);
                return 1;
            }
            if (as_handed_on(sp, cfg, ctrl.cycle + 1, &goal) != 0) {
                printf("DIFFERS at cycle %" PRId64 ": goal %" PRId64 " cannot be slowed to %.17g of its speed, as "
                       "the log shows\n",
                       sp->cycle, sp->input_goal_id, sp->input_goal_share);
                return 1;
            }
            in.goal = &goal;
            goals++;
        }
        if (sp->input_seated) {
            /* Seated where the drives were: the step's q is that position. */
            kc_real q[KC_MAX_JOINTS];
            for (j = 0; j < n; j++)
                q[j] = (kc_real)sp->q[j];
            st = kc_ctrl_seat(&ctrl, q, NULL);
            if (st != KC_OK) {
                printf("DIFFERS at cycle %" PRId64 ": the controller refuses the seat the log shows (%s)\n", sp->cycle,
                       kc_status_str(st));
                return 1;
            }
        }
        in.command = (kc_ctrl_command)sp->input_command;
        in.servo_stale = sp->input_servo_stale != 0;
        in.fault = sp->input_fault != 0 ? KC_REASON_EXTERNAL : KC_REASON_NONE;
        commands += in.command != KC_CMD_NONE;
        stale += in.servo_stale;
        st = kc_ctrl_step(&ctrl, &in, &out);
        if (st < 0) {
            printf("DIFFERS at cycle %" PRId64 ": the controller refused the step (%s)\n", sp->cycle,
                   kc_status_str(st));
            return 1;
        }
        if (out.cycle + base != sp->cycle) {
            printf("DIFFERS at cycle %" PRId64 ": the replay is at cycle %" PRId64 "\n", sp->cycle, out.cycle + base);
            return 1;
        }
        if (!compare(sp, &out, n)) {
            printf("  bit-exact before it: cycles %" PRId64 " .. %" PRId64 " (%zu cycles); active goal logged %" PRId64
                   "\n",
                   base + 1, sp->cycle - 1, i - 1 - start, sp->goal_id);
            return 1;
        }
        if (progress && (i - start) % PROGRESS_EVERY == 0)
            fprintf(stderr, "progress %zu %zu\n", i - start, r->n_sp - 1 - start);
    }
    if (progress)
        fprintf(stderr, "progress %zu %zu\n", r->n_sp - 1 - start, r->n_sp - 1 - start);
    printf("BIT-EXACT: %zu setpoints reproduced bit for bit (cycles %" PRId64 " .. %" PRId64 "), %ld goals, "
           "%ld commands, %ld stale servo ticks\n",
           r->n_sp - 1 - start, base + 1, r->sp[r->n_sp - 1].cycle, goals, commands, stale);
    return 0;
}

/* kinctld's options that take a separate value (kd_config_load's). */
static int takes_value(const char *arg)
{
    static const char *const opts[] = {"-c", "--config", "-m", "--model", "-p", "--period-us",
                                       "-P", "--prefix", "-u", "--lcm-url", NULL};
    int i;
    for (i = 0; opts[i] != NULL; i++)
        if (strcmp(arg, opts[i]) == 0)
            return 1;
    return 0;
}

int main(int argc, char **argv)
{
    static kd_config cfg;
    recording rec;
    const char *log_path = NULL;
    char **rest = calloc((size_t)argc + 1, sizeof *rest);
    int n_rest = 0, progress = 0, i, rc;
    kd_config_result cr;

    if (rest == NULL)
        return 2;
    rest[n_rest++] = argv[0];
    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            usage(stdout);
            free(rest);
            return 0;
        }
        if (strcmp(argv[i], "--version") == 0 || strcmp(argv[i], "-V") == 0) {
            printf("kinctl-replay %s\n", KC_VERSION);
            free(rest);
            return 0;
        }
        if (strcmp(argv[i], "--progress") == 0) {
            progress = 1;
        } else if (takes_value(argv[i]) && i + 1 < argc) {
            rest[n_rest++] = argv[i++];
            rest[n_rest++] = argv[i];
        } else if (argv[i][0] != '-' && log_path == NULL) {
            log_path = argv[i];
        } else {
            rest[n_rest++] = argv[i];
        }
    }
    if (log_path == NULL) {
        fprintf(stderr, "kinctl-replay: no LOG given (see --help)\n");
        free(rest);
        return 2;
    }
    cr = kd_config_load(&cfg, n_rest, rest);
    free(rest);
    if (cr != KD_CONFIG_RUN)
        return cr == KD_CONFIG_EXIT ? 0 : 2;
    kd_msg_init();
    memset(&rec, 0, sizeof rec);
    if (read_log(log_path, cfg.prefix, &rec) != 0)
        return 2;
    if (rec.n_sp == 0) {
        fprintf(stderr, "kinctl-replay: %s has no %sSETPOINT messages (another --prefix?)\n", log_path, cfg.prefix);
        rc = 2;
    } else if (rec.sp[0].n != cfg.chain.n_joints) {
        fprintf(stderr, "kinctl-replay: the log's setpoints have %d joints, the arm (%s) has %d: give the daemon's "
                        "--config or --model\n",
                (int)rec.sp[0].n, cfg.robot_name, cfg.chain.n_joints);
        rc = 2;
    } else {
        rc = replay(&rec, &cfg, progress);
    }
    free(rec.sp);
    free(rec.goals);
    return rc;
}
