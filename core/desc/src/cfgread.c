/* SPDX-License-Identifier: BSD-3-Clause */
/* cfgread.c - typed lookups in a parsed libconfig file (kinctl/cfgread.h). */
#include "kinctl/cfgread.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void write_error(kc_desc_error *e, const char *file, int line, const char *problem)
{
    snprintf(e->file, sizeof e->file, "%s", file);
    e->line = line;
    snprintf(e->problem, sizeof e->problem, "%s", problem);
    if (line > 0)
        snprintf(e->text, sizeof e->text, "%s:%d: %s", e->file, line, e->problem);
    else
        snprintf(e->text, sizeof e->text, "%s: %s", e->file, e->problem);
}

void kc_cfg_report(kc_cfg *r, const config_setting_t *s, const char *fmt, ...)
{
    char problem[KC_DESC_TEXT_LEN];
    const char *file = s != NULL ? config_setting_source_file(s) : NULL;
    va_list ap;
    if (r->err == NULL)
        return;
    va_start(ap, fmt);
    vsnprintf(problem, sizeof problem, fmt, ap);
    va_end(ap);
    write_error(r->err, file != NULL ? file : r->file, s != NULL ? (int)config_setting_source_line(s) : 0, problem);
}

/* Parses path (text NULL) or text; on error tree is destroyed. */
static kc_status parse(kc_cfg *r, const char *path, const char *text, config_t *tree)
{
    int ok;
    if (path != NULL) {
        FILE *f = fopen(path, "r");
        if (f == NULL)
            return kc_cfg_fail(r, NULL, "cannot open: %s", strerror(errno));
        fclose(f);
    }
    config_init(tree);
    config_set_options(tree, CONFIG_OPTION_AUTOCONVERT);
    if (path != NULL) {
        /* @include "x.cfg" is resolved beside the including file. */
        const char *slash = strrchr(path, '/');
        if (slash != NULL) {
            size_t len = (size_t)(slash - path);
            char *dir = malloc(len + 2);
            if (dir != NULL) {
                memcpy(dir, path, len + (len == 0));
                dir[len + (len == 0)] = '\0';
                config_set_include_dir(tree, dir);
                free(dir); /* libconfig keeps its own copy */
            }
        }
        ok = config_read_file(tree, path);
    } else {
        ok = config_read_string(tree, text);
    }
    if (ok)
        return KC_OK;
    if (r->err != NULL) {
        const char *what = config_error_text(tree), *file = config_error_file(tree);
        const char *hint = "";
        char msg[KC_DESC_TEXT_LEN];
        if (what != NULL && strstr(what, "mismatched element type") != NULL)
            hint = " (an array [..] may not mix 1 and 1.5: write 1.0)";
        snprintf(msg, sizeof msg, "%s%s", what != NULL ? what : "parse error", hint);
        write_error(r->err, file != NULL ? file : r->file, config_error_line(tree), msg);
    }
    config_destroy(tree);
    return KC_E_ARG;
}

kc_status kc_cfg_parse_file(kc_cfg *r, const char *path, config_t *tree) { return parse(r, path, NULL, tree); }

kc_status kc_cfg_parse_string(kc_cfg *r, const char *text, config_t *tree) { return parse(r, NULL, text, tree); }

kc_status kc_cfg_check_keys(kc_cfg *r, const config_setting_t *group, const char *where, const char *const *allowed)
{
    int n = config_setting_length(group);
    for (int i = 0; i < n; i++) {
        const config_setting_t *s = config_setting_get_elem(group, (unsigned)i);
        const char *name = config_setting_name(s);
        int known = 0;
        for (const char *const *a = allowed; *a != NULL && !known; a++)
            known = name != NULL && strcmp(name, *a) == 0;
        if (!known) {
            char list[512] = "";
            size_t len = 0;
            for (const char *const *a = allowed; *a != NULL; a++) {
                int w = snprintf(list + len, sizeof list - len, "%s%s", a == allowed ? "" : ", ", *a);
                if (w < 0 || (size_t)w >= sizeof list - len)
                    break;
                len += (size_t)w;
            }
            return kc_cfg_fail(r, s, "unknown key \"%s\" in %s (expected one of: %s)", name != NULL ? name : "?",
                               where, list);
        }
    }
    return KC_OK;
}

kc_status kc_cfg_require(kc_cfg *r, const config_setting_t *group, const char *key, const char *where)
{
    if (config_setting_get_member(group, key) == NULL)
        return kc_cfg_fail(r, group, "%s: missing key \"%s\"", where, key);
    return KC_OK;
}

int kc_cfg_is_number(const config_setting_t *s)
{
    int t = config_setting_type(s);
    return t == CONFIG_TYPE_INT || t == CONFIG_TYPE_INT64 || t == CONFIG_TYPE_FLOAT;
}

double kc_cfg_value(const config_setting_t *s)
{
    if (config_setting_type(s) == CONFIG_TYPE_INT64)
        return (double)config_setting_get_int64(s);
    if (config_setting_type(s) == CONFIG_TYPE_INT)
        return (double)config_setting_get_int(s);
    return config_setting_get_float(s);
}

kc_status kc_cfg_number(kc_cfg *r, const config_setting_t *s, const char *what, double *out)
{
    if (!kc_cfg_is_number(s))
        return kc_cfg_fail(r, s, "%s must be a number", what);
    double v = kc_cfg_value(s);
    if (!isfinite(v))
        return kc_cfg_fail(r, s, "%s is not a finite number", what);
    *out = v;
    return KC_OK;
}

kc_status kc_cfg_real(kc_cfg *r, const config_setting_t *s, const char *what, kc_real scale, kc_real *out)
{
    double d = 0.0;
    kc_status st = kc_cfg_number(r, s, what, &d);
    if (st != KC_OK)
        return st;
    kc_real v = (kc_real)d * scale;
    if (!kc_isfinite(v))
        return kc_cfg_fail(r, s, "%s is not a finite number", what);
    *out = v;
    return KC_OK;
}

kc_status kc_cfg_vector_real(kc_cfg *r, const config_setting_t *s, const char *what, int n, kc_real scale,
                             kc_real *out)
{
    if (!config_setting_is_array(s) && !config_setting_is_list(s))
        return kc_cfg_fail(r, s, "%s must be a vector of %d numbers, e.g. [0.0, 0.0, 0.0]", what, n);
    if (config_setting_length(s) != n)
        return kc_cfg_fail(r, s, "%s must hold %d numbers, not %d", what, n, config_setting_length(s));
    for (int i = 0; i < n; i++) {
        char item[112];
        snprintf(item, sizeof item, "%s[%d]", what, i);
        kc_status st = kc_cfg_real(r, config_setting_get_elem(s, (unsigned)i), item, scale, &out[i]);
        if (st != KC_OK)
            return st;
    }
    return KC_OK;
}

/* The name of group's key in messages: where, the separator, key. */
static const char *name_of(const kc_cfg *r, const char *where, const char *key, char *buf, size_t size)
{
    snprintf(buf, size, "%s%s%s", where, r->sep, key);
    return buf;
}

kc_status kc_cfg_lookup_real(kc_cfg *r, const config_setting_t *group, const char *key, const char *where,
                             int required, kc_real scale, kc_real *out, int *present)
{
    const config_setting_t *s = config_setting_get_member(group, key);
    char what[160];
    if (present != NULL)
        *present = s != NULL;
    if (s == NULL)
        return required ? kc_cfg_require(r, group, key, where) : KC_OK;
    return kc_cfg_real(r, s, name_of(r, where, key, what, sizeof what), scale, out);
}

kc_status kc_cfg_lookup_number(kc_cfg *r, const config_setting_t *group, const char *key, const char *where,
                               double lo, double hi, double *out)
{
    const config_setting_t *s = config_setting_get_member(group, key);
    char what[160];
    double v = 0.0;
    kc_status st;
    if (s == NULL)
        return KC_OK;
    name_of(r, where, key, what, sizeof what);
    if ((st = kc_cfg_number(r, s, what, &v)) != KC_OK)
        return st;
    if (v < lo || v > hi)
        return kc_cfg_fail(r, s, "%s = %.17g is outside %g .. %g", what, v, lo, hi);
    *out = v;
    return KC_OK;
}

kc_status kc_cfg_lookup_int(kc_cfg *r, const config_setting_t *group, const char *key, const char *where, int lo,
                            int hi, int *out)
{
    const config_setting_t *s = config_setting_get_member(group, key);
    char what[160];
    long long v;
    if (s == NULL)
        return KC_OK;
    name_of(r, where, key, what, sizeof what);
    if (config_setting_type(s) == CONFIG_TYPE_INT)
        v = config_setting_get_int(s);
    else if (config_setting_type(s) == CONFIG_TYPE_INT64)
        v = config_setting_get_int64(s);
    else
        return kc_cfg_fail(r, s, "%s must be an integer", what);
    if (v < lo || v > hi)
        return kc_cfg_fail(r, s, "%s = %lld is outside %d .. %d", what, v, lo, hi);
    *out = (int)v;
    return KC_OK;
}

kc_status kc_cfg_lookup_bool(kc_cfg *r, const config_setting_t *group, const char *key, const char *where, int *out)
{
    const config_setting_t *s = config_setting_get_member(group, key);
    char what[160];
    if (s == NULL)
        return KC_OK;
    if (config_setting_type(s) != CONFIG_TYPE_BOOL)
        return kc_cfg_fail(r, s, "%s must be true or false", name_of(r, where, key, what, sizeof what));
    *out = config_setting_get_bool(s);
    return KC_OK;
}

kc_status kc_cfg_lookup_string(kc_cfg *r, const config_setting_t *group, const char *key, const char *where,
                               const char **out, const config_setting_t **found)
{
    const config_setting_t *s = config_setting_get_member(group, key);
    char what[160];
    if (found != NULL)
        *found = NULL;
    if (s == NULL)
        return KC_OK;
    if (config_setting_type(s) != CONFIG_TYPE_STRING)
        return kc_cfg_fail(r, s, "%s must be a string in double quotes", name_of(r, where, key, what, sizeof what));
    *out = config_setting_get_string(s);
    if (found != NULL)
        *found = s;
    return KC_OK;
}

kc_status kc_cfg_string(kc_cfg *r, const config_setting_t *group, const char *key, const char *where,
                        const char **out)
{
    kc_status st = kc_cfg_require(r, group, key, where);
    return st != KC_OK ? st : kc_cfg_lookup_string(r, group, key, where, out, NULL);
}

kc_status kc_cfg_lookup_group(kc_cfg *r, const config_setting_t *group, const char *key, const char *where,
                              const config_setting_t **out)
{
    const config_setting_t *s = config_setting_get_member(group, key);
    char what[160];
    *out = NULL;
    if (s != NULL && !config_setting_is_group(s))
        return kc_cfg_fail(r, s, "%s must be a group { ... }", name_of(r, where, key, what, sizeof what));
    *out = s;
    return KC_OK;
}
