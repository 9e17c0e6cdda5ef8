/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * kinctl/cfgread.h - reading a parsed libconfig file: typed lookups whose
 * problems name the file and the line, "<file>:<line>: <problem>".
 *
 * The description library reads robot descriptions and zones with these
 * (desc.c, zones.c), and kinctld its controller section (daemon/config_file.c,
 * daemon/can_config.c), so a file that holds both reads alike throughout.
 * Not installed (cmake/install.cmake): it exposes libconfig, which
 * kinctl::desc links privately.
 *
 * A setting is named in messages by where it is and its key, joined by the
 * reader's separator: the description library says where a setting is
 * ("dh row 2: alpha", separator ": "), kinctld gives its path
 * ("controller.can.sync_every", separator ".").
 *
 * Every lookup of an optional key leaves its output untouched when the key
 * is absent, returns KC_OK or KC_E_ARG, and on error records the problem in
 * the reader's kc_desc_error (the first one a reader returns on). At
 * start-up only, never in the cycle.
 */
#ifndef KINCTL_CFGREAD_H
#define KINCTL_CFGREAD_H

#include <libconfig.h>

#include "kinctl/decls.h"
#include "kinctl/desc.h"

KC_BEGIN_DECLS

#if defined(__GNUC__)
#define KC_CFG_PRINTF(f, a) __attribute__((format(printf, f, a)))
#else
#define KC_CFG_PRINTF(f, a)
#endif

/* One reading of one file. */
typedef struct kc_cfg {
    /* The input's name where a setting has no file of its own (an
     * @include'd setting names its own file). */
    const char *file;
    /* Joins where and key in messages: ": " or ".". */
    const char *sep;
    /* Where problems go (NULL: nowhere). */
    kc_desc_error *err;
} kc_cfg;

/* Records "<file>:<line>: <problem>" at setting s (s NULL: no line). */
void kc_cfg_report(kc_cfg *r, const config_setting_t *s, const char *fmt, ...) KC_CFG_PRINTF(3, 4);

/* Report and evaluate to a status, so that readers write `return
 * kc_cfg_fail(...)`; macros, so that the status returned is plain where it
 * is returned (static analyzers do not follow calls into variadic
 * functions). */
#define kc_cfg_fail_at(r, s, st, ...) (kc_cfg_report((r), (s), __VA_ARGS__), (st))
#define kc_cfg_fail(r, s, ...) kc_cfg_fail_at((r), (s), KC_E_ARG, __VA_ARGS__)

/* Parses the file at path (@include resolved beside it) or the text into
 * tree, with libconfig's AUTOCONVERT. On error records it (the file and
 * line libconfig names) and leaves tree destroyed; on success the caller
 * calls config_destroy(tree). */
kc_status kc_cfg_parse_file(kc_cfg *r, const char *path, config_t *tree);
kc_status kc_cfg_parse_string(kc_cfg *r, const char *text, config_t *tree);

/* Every key of group must be in allowed (NULL-terminated): "unknown key
 * "x" in <where> (expected one of: a, b, c)". */
kc_status kc_cfg_check_keys(kc_cfg *r, const config_setting_t *group, const char *where, const char *const *allowed);

/* The required key must be there: "<where>: missing key "<key>"" at group. */
kc_status kc_cfg_require(kc_cfg *r, const config_setting_t *group, const char *key, const char *where);

/* Whether s is an integer or a decimal. */
int kc_cfg_is_number(const config_setting_t *s);

/* The value of s, a number (kc_cfg_is_number), as a double; reports
 * nothing. */
double kc_cfg_value(const config_setting_t *s);

/* s as a finite number (what names it in messages). */
kc_status kc_cfg_number(kc_cfg *r, const config_setting_t *s, const char *what, double *out);

/* s as a finite number times scale, finite in kc_real (a value in the
 * file's unit to the chain's). */
kc_status kc_cfg_real(kc_cfg *r, const config_setting_t *s, const char *what, kc_real scale, kc_real *out);

/* s as a vector of n such numbers: an array [..] or a list (..). */
kc_status kc_cfg_vector_real(kc_cfg *r, const config_setting_t *s, const char *what, int n, kc_real scale,
                             kc_real *out);

/* An optional (required 0) or required (1) key read by kc_cfg_real;
 * *present (may be NULL) says whether it was there. */
kc_status kc_cfg_lookup_real(kc_cfg *r, const config_setting_t *group, const char *key, const char *where,
                             int required, kc_real scale, kc_real *out, int *present);

/* Optional keys of group. A number within [lo, hi]; an integer within
 * [lo, hi]; a boolean. */
kc_status kc_cfg_lookup_number(kc_cfg *r, const config_setting_t *group, const char *key, const char *where,
                               double lo, double hi, double *out);
kc_status kc_cfg_lookup_int(kc_cfg *r, const config_setting_t *group, const char *key, const char *where, int lo,
                            int hi, int *out);
kc_status kc_cfg_lookup_bool(kc_cfg *r, const config_setting_t *group, const char *key, const char *where, int *out);

/* An optional string: *out set when present; found (may be NULL) gets the
 * setting, or NULL when absent. */
kc_status kc_cfg_lookup_string(kc_cfg *r, const config_setting_t *group, const char *key, const char *where,
                               const char **out, const config_setting_t **found);

/* A required string key. */
kc_status kc_cfg_string(kc_cfg *r, const config_setting_t *group, const char *key, const char *where,
                        const char **out);

/* An optional group { ... }: *out is the setting, or NULL when absent. */
kc_status kc_cfg_lookup_group(kc_cfg *r, const config_setting_t *group, const char *key, const char *where,
                              const config_setting_t **out);

KC_END_DECLS

#endif /* KINCTL_CFGREAD_H */
