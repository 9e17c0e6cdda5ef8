/* SPDX-License-Identifier: BSD-3-Clause */
/* args.c - command-line arguments to request objects, and the typed getters
 * every subcommand reads its request with (the same for the command line and
 * for batch lines). */
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "calc.h"
#include "kinctl/desc.h"

void calc_report(calc_ctx *ctx, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(ctx->err, sizeof ctx->err, fmt, ap); // NOLINT(clang-analyzer-valist.Uninitialized): va_start is above
    va_end(ap);
}

void calc_warn(calc_ctx *ctx, const char *fmt, ...)
{
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap); // NOLINT(clang-analyzer-valist.Uninitialized): va_start is above
    va_end(ap);
    if (ctx->warnings != NULL)
        json_array_append_new(ctx->warnings, json_string(msg));
}

/* ---- converters ---- */

static int parse_real(const char *s, size_t n, double *out, char *err, size_t errlen)
{
    char buf[64];
    char *end = NULL;
    if (n == 0 || n >= sizeof buf) {
        snprintf(err, errlen, n == 0 ? "empty number" : "number too long: \"%.*s...\"", 20, s);
        return -1;
    }
    memcpy(buf, s, n);
    buf[n] = '\0';
    errno = 0;
    double v = strtod(buf, &end);
    if (end == buf || *end != '\0') {
        snprintf(err, errlen, "not a number: \"%s\"", buf);
        return -1;
    }
    if (!kc_isfinite((kc_real)v)) {
        snprintf(err, errlen, "not a finite number: \"%s\"", buf);
        return -1;
    }
    *out = v;
    return 0;
}

json_t *calc_conv_string(const char *arg, char *err, size_t errlen)
{
    json_t *v = json_string(arg);
    if (v == NULL)
        snprintf(err, errlen, "not valid UTF-8: \"%s\"", arg);
    return v;
}

json_t *calc_conv_real(const char *arg, char *err, size_t errlen)
{
    double v;
    return parse_real(arg, strlen(arg), &v, err, errlen) == 0 ? json_real(v) : NULL;
}

json_t *calc_conv_reals(const char *arg, char *err, size_t errlen)
{
    json_t *arr = json_array();
    const char *p = arg;
    for (;;) {
        const char *comma = strchr(p, ',');
        size_t n = comma != NULL ? (size_t)(comma - p) : strlen(p);
        double v;
        if (parse_real(p, n, &v, err, errlen) != 0) {
            json_decref(arr);
            return NULL;
        }
        json_array_append_new(arr, json_real(v));
        if (comma == NULL)
            break;
        p = comma + 1;
    }
    return arr;
}

json_t *calc_conv_params(const char *arg, char *err, size_t errlen)
{
    json_t *obj = json_object();
    const char *p = arg;
    for (;;) {
        const char *comma = strchr(p, ',');
        size_t n = comma != NULL ? (size_t)(comma - p) : strlen(p);
        const char *eq = memchr(p, '=', n);
        char name[32];
        double v;
        if (eq == NULL || eq == p || (size_t)(eq - p) >= sizeof name) {
            snprintf(err, errlen, "expected NAME=VALUE, not \"%.*s\"", (int)n, p);
            json_decref(obj);
            return NULL;
        }
        memcpy(name, p, (size_t)(eq - p));
        name[eq - p] = '\0';
        if (parse_real(eq + 1, n - (size_t)(eq - p) - 1, &v, err, errlen) != 0) {
            json_decref(obj);
            return NULL;
        }
        json_object_set_new(obj, name, json_real(v));
        if (comma == NULL)
            break;
        p = comma + 1;
    }
    return obj;
}

/* ---- the command line ---- */

static int is_number_arg(const char *a)
{
    char *end = NULL;
    (void)strtod(a, &end);
    return end != a;
}

json_t *calc_parse_args(const calc_cmd *cmd, int argc, char **argv, char *err, size_t errlen)
{
    json_t *req = json_object();
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i];
        const calc_opt *opt = NULL;
        const char *value = NULL;
        size_t flag_len = strlen(a);
        int is_flag = a[0] == '-' && a[1] == '-';
        if (!is_flag && a[0] == '-' && !is_number_arg(a)) {
            snprintf(err, errlen, "unknown option \"%s\" (options start with --)", a);
            goto bad;
        }
        if (is_flag) {
            const char *eq = strchr(a, '=');
            if (eq != NULL) {
                flag_len = (size_t)(eq - a);
                value = eq + 1;
            }
        }
        for (const calc_opt *o = cmd->opts; o->key != NULL && opt == NULL; o++) {
            if (is_flag ? o->flag != NULL && strlen(o->flag) == flag_len && strncmp(o->flag, a, flag_len) == 0
                        : o->flag == NULL)
                opt = o;
        }
        if (opt == NULL) {
            if (is_flag)
                snprintf(err, errlen, "unknown option \"%.*s\"", (int)flag_len, a);
            else
                snprintf(err, errlen, "unexpected argument \"%s\"", a);
            goto bad;
        }
        if (opt->kind == CALC_FLAG) {
            if (value != NULL) {
                snprintf(err, errlen, "%s takes no value", opt->flag);
                goto bad;
            }
            json_object_set_new(req, opt->key, json_true());
            continue;
        }
        if (opt->flag == NULL) {
            value = a;
        } else if (value == NULL) {
            if (i + 1 >= argc) {
                snprintf(err, errlen, "%s needs a value (%s)", opt->flag, opt->metavar);
                goto bad;
            }
            value = argv[++i];
        }
        char why[256];
        json_t *v = opt->conv(value, why, sizeof why);
        if (v == NULL) {
            snprintf(err, errlen, "%s: %s", opt->flag != NULL ? opt->flag : opt->metavar, why);
            goto bad;
        }
        if (opt->kind == CALC_VALUE) {
            if (json_object_get(req, opt->key) != NULL) {
                snprintf(err, errlen, "%s given twice", opt->flag);
                json_decref(v);
                goto bad;
            }
            json_object_set_new(req, opt->key, v);
        } else {
            json_t *list = json_object_get(req, opt->key);
            if (list == NULL) {
                list = json_array();
                json_object_set_new(req, opt->key, list);
            }
            if (opt->kind == CALC_EXTEND && json_is_array(v)) {
                json_array_extend(list, v);
                json_decref(v);
            } else {
                json_array_append_new(list, v);
            }
        }
    }
    return req;
bad:
    json_decref(req);
    return NULL;
}

int calc_check_keys(calc_ctx *ctx, const json_t *req, const calc_cmd *cmd)
{
    const char *key;
    json_t *value;
    json_object_foreach((json_t *)req, key, value)
    {
        int known = strcmp(key, "op") == 0 || strcmp(key, "id") == 0;
        for (const calc_opt *o = cmd->opts; o->key != NULL && !known; o++)
            known = strcmp(o->key, key) == 0;
        if (!known)
            return calc_fail(ctx, "unknown key \"%s\" for op \"%s\"", key, cmd->name);
    }
    return 0;
}

/* ---- getters ---- */

int req_string(calc_ctx *ctx, const json_t *req, const char *key, int required, const char **out)
{
    const json_t *v = json_object_get(req, key);
    if (v == NULL)
        return required ? calc_fail(ctx, "missing %s", key) : 0;
    if (!json_is_string(v))
        return calc_fail(ctx, "%s must be a string", key);
    *out = json_string_value(v);
    return 0;
}

int req_bool(calc_ctx *ctx, const json_t *req, const char *key, int *out)
{
    const json_t *v = json_object_get(req, key);
    if (v == NULL)
        return 0;
    if (!json_is_boolean(v))
        return calc_fail(ctx, "%s must be true or false", key);
    *out = json_is_true(v);
    return 0;
}

static int real_of(calc_ctx *ctx, const json_t *v, const char *what, kc_real *out)
{
    if (!json_is_number(v))
        return calc_fail(ctx, "%s must be a number", what);
    kc_real x = (kc_real)json_number_value(v);
    if (!kc_isfinite(x))
        return calc_fail(ctx, "%s is not a finite number", what);
    *out = x;
    return 0;
}

int req_real(calc_ctx *ctx, const json_t *req, const char *key, kc_real *out)
{
    const json_t *v = json_object_get(req, key);
    if (v == NULL)
        return calc_fail(ctx, "missing %s", key);
    return real_of(ctx, v, key, out);
}

int req_positive(calc_ctx *ctx, const json_t *req, const char *key, int required, const char *unit, kc_real *out)
{
    if (!required && json_object_get(req, key) == NULL)
        return 0;
    if (req_real(ctx, req, key, out) != 0)
        return -1;
    if (!(*out > KC_R(0.0)))
        return calc_fail(ctx, "%s must be > 0 %s, not %g", key, unit, (double)*out);
    return 0;
}

int rate_in_range(calc_ctx *ctx, const char *key, kc_real x)
{
    if (!(x >= (kc_real)KC_DESC_RATE_MIN && x <= (kc_real)KC_DESC_RATE_MAX))
        return calc_fail(ctx, "%s = %g is outside %g .. %g (in rad or m)", key, (double)x, KC_DESC_RATE_MIN,
                         KC_DESC_RATE_MAX);
    return 0;
}

int req_rate(calc_ctx *ctx, const json_t *req, const char *key, int required, const char *unit, kc_real *out)
{
    int present = json_object_get(req, key) != NULL;
    if (req_positive(ctx, req, key, required, unit, out) != 0)
        return -1;
    return present ? rate_in_range(ctx, key, *out) : 0;
}

int req_reals(calc_ctx *ctx, const json_t *v, const char *what, kc_real *out, int max, int *n)
{
    if (v == NULL)
        return calc_fail(ctx, "missing %s", what);
    if (!json_is_array(v))
        return calc_fail(ctx, "%s must be an array of numbers", what);
    if (json_array_size(v) > (size_t)max)
        return calc_fail(ctx, "%s has %zu values, at most %d allowed", what, json_array_size(v), max);
    for (size_t i = 0; i < json_array_size(v); i++) {
        char item[64];
        snprintf(item, sizeof item, "%s[%zu]", what, i);
        if (real_of(ctx, json_array_get(v, i), item, &out[i]) != 0)
            return -1;
    }
    *n = (int)json_array_size(v);
    return 0;
}

/* rrr3 takes l1, l2, l3 and planar2 l1, l2 (m, > 0). */
static int model_params(calc_ctx *ctx, const json_t *param, kc_model model, kc_model_params *out)
{
    int count = model == KC_MODEL_RRR3 ? 3 : model == KC_MODEL_PLANAR2 ? 2 : 0;
    const char *key;
    json_t *value;
    memset(out, 0, sizeof *out);
    if (!json_is_object(param))
        return calc_fail(ctx, "param must be an object such as {\"l1\": 0.4}");
    if (count == 0)
        return calc_fail(ctx, "model %s takes no parameters", kc_model_name(model));
    json_object_foreach((json_t *)param, key, value)
    {
        int i = -1;
        if (key[0] == 'l' && key[1] >= '1' && key[1] < (char)('1' + count) && key[2] == '\0')
            i = key[1] - '1';
        if (i < 0)
            return calc_fail(ctx, "model %s has no parameter \"%s\" (it takes l1..l%d)", kc_model_name(model), key,
                             count);
        if (real_of(ctx, value, key, &out->len[i]) != 0)
            return -1;
        if (!(out->len[i] > KC_R(0.0)))
            return calc_fail(ctx, "parameter %s must be > 0 m", key);
    }
    return 0;
}

int req_model(calc_ctx *ctx, const json_t *req, kc_chain *chain)
{
    const char *name = NULL, *path = NULL;
    const json_t *param = json_object_get(req, "param");
    if (req_string(ctx, req, "model", 0, &name) != 0 || req_string(ctx, req, "model_file", 0, &path) != 0)
        return -1;
    if ((name == NULL) == (path == NULL))
        return calc_fail(ctx, name == NULL ? "give a model: --model NAME or --model-file PATH"
                                           : "give either --model or --model-file, not both");
    if (path != NULL) {
        kc_desc_error err;
        if (param != NULL)
            return calc_fail(ctx, "--param applies to built-in models only; edit the file instead");
        if (kc_desc_load_file(path, chain, NULL, &err) != KC_OK)
            return calc_fail(ctx, "%s", err.text);
        return 0;
    }
    int m = kc_model_from_name(name);
    if (m < 0)
        return calc_fail(ctx, "unknown model \"%s\" (built-in: puma560, panda, rrr3, planar2, rb211, rm01)", name);
    kc_model_params params;
    if (param != NULL && model_params(ctx, param, (kc_model)m, &params) != 0)
        return -1;
    kc_status st = kc_chain_init_model(chain, (kc_model)m, param != NULL ? &params : NULL);
    if (st != KC_OK)
        return calc_fail(ctx, "cannot build model %s: %s", name, kc_status_str(st));
    return 0;
}

kc_real joint_shown(const kc_chain *chain, int j, int deg)
{
    return deg && chain->joints[j].type == KC_JOINT_REVOLUTE ? KC_R(1.0) / KC_DEG : KC_R(1.0);
}

const char *joint_unit(const kc_chain *chain, int j, int deg)
{
    return chain->joints[j].type != KC_JOINT_REVOLUTE ? "m" : deg ? "deg" : "rad";
}

int req_joints(calc_ctx *ctx, const json_t *req, const char *key, const kc_chain *chain, int deg, kc_real *q)
{
    int n = 0;
    if (req_reals(ctx, json_object_get(req, key), key, q, KC_MAX_JOINTS, &n) != 0)
        return -1;
    if (n != chain->n_joints)
        return calc_fail(ctx, "%s has %d values but the model has %d joints", key, n, chain->n_joints);
    for (int j = 0; j < n; j++) {
        const kc_joint *jt = &chain->joints[j];
        kc_real s = joint_shown(chain, j, deg);
        if (deg && jt->type == KC_JOINT_REVOLUTE)
            q[j] *= KC_DEG;
        if (q[j] < jt->limits.q_min || q[j] > jt->limits.q_max)
            calc_warn(ctx, "%s[%d] = %g %s is outside joint %d's limits [%g, %g]", key, j, (double)(q[j] * s),
                      joint_unit(chain, j, deg), j + 1, (double)(jt->limits.q_min * s),
                      (double)(jt->limits.q_max * s));
    }
    return 0;
}

int req_q(calc_ctx *ctx, const json_t *req, const kc_chain *chain, int deg, kc_real *q)
{
    return req_joints(ctx, req, "q", chain, deg, q);
}
