/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * calc.h - the pieces kinctl-calc's subcommands share.
 *
 * A subcommand is one run function plus one entry in the table of
 * kinctl-calc.c. Its options are declared once (calc_opt): the command line
 * parser turns them into a JSON request object, and `kinctl-calc batch`
 * reads the same object from a line of stdin, so run() sees one form only.
 * run() writes the members of its result object with the jw_* writer and
 * returns 0, or returns calc_fail(...) with a message.
 */
#ifndef KINCTL_CALC_H
#define KINCTL_CALC_H

#include <stddef.h>

#include <jansson.h>

#include "kinctl/kinctl.h"

/* ---- JSON output (json_out.c) ---- */

#define JW_MAX_DEPTH 16

/* A growable buffer holding one JSON value, written in order. */
typedef struct jw {
    char *buf;
    size_t len, cap;
    int depth;
    int count[JW_MAX_DEPTH];
    int after_key;
    int failed; /* out of memory */
} jw;

void jw_init(jw *w);
void jw_free(jw *w);
void jw_obj_begin(jw *w);
void jw_obj_end(jw *w);
void jw_arr_begin(jw *w);
void jw_arr_end(jw *w);
void jw_key(jw *w, const char *key);
/* Every digit needed to read the value back ("%.17g" for double); null for
 * a value that JSON cannot hold (NaN, infinity). */
void jw_real(jw *w, kc_real x);
void jw_bool(jw *w, int b);
void jw_null(jw *w);
void jw_str(jw *w, const char *s);
/* A JSON value given as text (already valid JSON). */
void jw_raw(jw *w, const char *json);
void jw_reals(jw *w, const kc_real *x, int n);
/* A pose as its 4x4 homogeneous matrix. */
void jw_pose(jw *w, const kc_pose *p);
void jw_mat3(jw *w, const kc_mat3 *m);
void jw_mat4(jw *w, const kc_mat4 *m);

/* ---- requests (args.c) ---- */

/* How a run reports back: the result writer, the error message, warnings. */
typedef struct calc_ctx {
    jw *out;
    char err[1024];
    json_t *warnings; /* array of strings */
    int csv;          /* interp on the command line: rows go to stdout as CSV */
} calc_ctx;

/* Sets ctx->err. */
void calc_report(calc_ctx *ctx, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
/* Sets ctx->err and evaluates to -1; a macro so that the -1 is plain where it
 * is returned (static analyzers do not follow calls into variadic functions). */
#define calc_fail(ctx, ...) (calc_report((ctx), __VA_ARGS__), -1)
void calc_warn(calc_ctx *ctx, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Turns one command-line argument into a JSON value; NULL with err set
 * when the argument is malformed. */
typedef json_t *(*calc_conv)(const char *arg, char *err, size_t errlen);

typedef enum calc_opt_kind {
    CALC_FLAG,   /* --deg: key = true */
    CALC_VALUE,  /* --model NAME: key = conv(NAME), at most once */
    CALC_APPEND, /* --point X,Y,Z (repeatable): key = [..., conv(arg)] */
    CALC_EXTEND  /* positionals (flag NULL): key = [..., elements of conv(arg)] */
} calc_opt_kind;

typedef struct calc_opt {
    const char *flag; /* "--model", or NULL for the positional arguments */
    const char *key;  /* key in the request object */
    calc_opt_kind kind;
    calc_conv conv;
    const char *metavar;
    const char *help;
} calc_opt;

typedef struct calc_cmd {
    const char *name;
    const char *summary;
    const char *usage; /* usage line(s), details and an example */
    const calc_opt *opts; /* terminated by an entry with key NULL */
    int (*run)(const json_t *req, calc_ctx *ctx);
} calc_cmd;

/* Converters for calc_opt. */
json_t *calc_conv_string(const char *arg, char *err, size_t errlen);
json_t *calc_conv_reals(const char *arg, char *err, size_t errlen);
json_t *calc_conv_real(const char *arg, char *err, size_t errlen);
json_t *calc_conv_params(const char *arg, char *err, size_t errlen);

/* Parses argv (after the subcommand name) into a request object; NULL with
 * err set on bad usage. */
json_t *calc_parse_args(const calc_cmd *cmd, int argc, char **argv, char *err, size_t errlen);

/* Fails on a key of req that cmd does not declare ("op" and "id" are
 * always allowed). */
int calc_check_keys(calc_ctx *ctx, const json_t *req, const calc_cmd *cmd);

/* Getters: 0 when fine (an absent optional key leaves *out alone), else
 * calc_fail. */
int req_string(calc_ctx *ctx, const json_t *req, const char *key, int required, const char **out);
int req_bool(calc_ctx *ctx, const json_t *req, const char *key, int *out);
int req_real(calc_ctx *ctx, const json_t *req, const char *key, kc_real *out);
/* A finite number > 0 (unit names it in the message). */
int req_positive(calc_ctx *ctx, const json_t *req, const char *key, int required, const char *unit, kc_real *out);
/* req_positive for a rate limit (a speed, an acceleration, a jerk): within
 * KC_DESC_RATE_MIN .. KC_DESC_RATE_MAX (kinctl/desc.h) as well. */
int req_rate(calc_ctx *ctx, const json_t *req, const char *key, int required, const char *unit, kc_real *out);
/* 0 when x, a rate limit named key (in rad or m), lies within that range;
 * else the error, as calc_fail. */
int rate_in_range(calc_ctx *ctx, const char *key, kc_real x);
/* An array of finite numbers; *n gets the count (at most max). */
int req_reals(calc_ctx *ctx, const json_t *v, const char *what, kc_real *out, int max, int *n);
/* The model: model (a built-in name) with optional param, or model_file. */
int req_model(calc_ctx *ctx, const json_t *req, kc_chain *chain);
/* Joint values under key for chain (n_joints values; revolute ones in deg
 * when deg); warns when they lie outside the joint limits. */
int req_joints(calc_ctx *ctx, const json_t *req, const char *key, const kc_chain *chain, int deg, kc_real *q);
/* Joint j's values as shown: the factor from the chain's units (rad, m)
 * and the unit's name; with deg, a revolute joint's in degrees. */
kc_real joint_shown(const kc_chain *chain, int j, int deg);
const char *joint_unit(const kc_chain *chain, int j, int deg);
/* req_joints for the key "q". */
int req_q(calc_ctx *ctx, const json_t *req, const kc_chain *chain, int deg, kc_real *q);

/* The options that choose the model, for a calc_opt table. */
#define CALC_CHAIN_OPTS                                                                                  \
    {"--model", "model", CALC_VALUE, calc_conv_string, "NAME",                                         \
     "built-in model: puma560, panda, rrr3, planar2, rb211, rm01"},                                    \
    {"--model-file", "model_file", CALC_VALUE, calc_conv_string, "PATH", "robot description file (.cfg)"}, \
    {"--param", "param", CALC_VALUE, calc_conv_params, "l1=..,l2=..",                                  \
     "link lengths in m of rrr3 (l1, l2, l3) or planar2 (l1, l2)"}

/* The options every model-based subcommand at one configuration takes. */
#define CALC_MODEL_OPTS                                                                                  \
    CALC_CHAIN_OPTS,                                                                                     \
    {"--q", "q", CALC_VALUE, calc_conv_reals, "Q1,Q2,...", "joint values, rad or m (deg with --deg)"},  \
    {"--deg", "deg", CALC_FLAG, NULL, NULL, "revolute joint values in degrees"}

/* ---- subcommands defined in their own files ---- */

/* zones.c: link volumes against forbidden zones. */
extern const calc_opt zones_opts[];
int run_zones(const json_t *req, calc_ctx *ctx);

/* ik.c: inverse kinematics to a target pose. */
extern const calc_opt ik_opts[];
int run_ik(const json_t *req, calc_ctx *ctx);

/*
 * interp.c: `kinctl-calc interp KIND [OPTIONS]`, sampled motions.
 *
 * Dispatch: main() hands every argument after "interp" to calc_interp_main,
 * which takes the second word as KIND and looks it up in interp.c's table
 * of kinds: joint, line and arc (run_interp_joint/line/arc in interp.c) and
 * path (run_interp_path, interp_path.c). Each kind is a calc_cmd of its own
 * (its option table and run function), so its options are parsed and
 * checked exactly like a subcommand's, and `interp KIND --help` prints them.
 * In batch the op is "interp" with "kind": KIND and the kind's keys
 * (run_interp); interp_opts lists every kind's keys for batch --help.
 *
 * A kind's run(req, ctx) writes its samples with the calc_rows_* calls
 * below, one row per tick from t = 0 to the end inclusive: CSV with a header
 * row on the command line (ctx->csv), "columns" and "rows" members in batch.
 *
 * The path kind plugs in as the one function run_interp_path, defined in
 * interp_path.c; its options are interp_path_opts in interp.c (the issue's
 * list: space, method, points, times, velocities, tacc, v, a, dt; add a line
 * there for another). tools/CMakeLists.txt compiles interp_path.c in when
 * it exists (KINCTL_CALC_HAVE_INTERP_PATH); until then `interp path`
 * answers that it is not yet available.
 */
extern const calc_opt interp_opts[];
extern const calc_opt interp_path_opts[];
int calc_interp_main(int argc, char **argv);
int run_interp(const json_t *req, calc_ctx *ctx);
int run_interp_path(const json_t *req, calc_ctx *ctx);

/* Rows of samples: begin with the ncol column names, add rows of ncol
 * values (the same ncol), end. */
void calc_rows_begin(calc_ctx *ctx, int ncol, const char *const *names);
void calc_rows_add(calc_ctx *ctx, int ncol, const kc_real *row);
void calc_rows_end(calc_ctx *ctx);

#endif /* KINCTL_CALC_H */
