/* SPDX-License-Identifier: BSD-3-Clause */
/* json_out.c - a small JSON writer for kinctl-calc's answers. Values are
 * printed with every significant digit so that they read back exactly. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "calc.h"

#ifdef KC_REAL_FLOAT
#define REAL_FMT "%.9g"
#else
#define REAL_FMT "%.17g"
#endif

void jw_init(jw *w) { memset(w, 0, sizeof *w); }

void jw_free(jw *w)
{
    free(w->buf);
    jw_init(w);
}

static void put(jw *w, const char *s, size_t n)
{
    if (w->failed)
        return;
    if (w->len + n + 1 > w->cap) {
        size_t cap = w->cap != 0 ? w->cap : 256;
        while (w->len + n + 1 > cap)
            cap *= 2;
        char *buf = realloc(w->buf, cap);
        if (buf == NULL) {
            w->failed = 1;
            return;
        }
        w->buf = buf;
        w->cap = cap;
    }
    memcpy(w->buf + w->len, s, n);
    w->len += n;
    w->buf[w->len] = '\0';
}

static void puts_(jw *w, const char *s) { put(w, s, strlen(s)); }

/* A comma before every value but the first of its container, none right
 * after a key. */
static void value_prefix(jw *w)
{
    if (w->after_key) {
        w->after_key = 0;
        return;
    }
    if (w->count[w->depth]++ > 0)
        puts_(w, ",");
}

static void begin(jw *w, const char *open)
{
    value_prefix(w);
    puts_(w, open);
    if (w->depth + 1 < JW_MAX_DEPTH)
        w->depth++;
    else
        w->failed = 1;
    w->count[w->depth] = 0;
}

static void end(jw *w, const char *close)
{
    puts_(w, close);
    if (w->depth > 0)
        w->depth--;
}

void jw_obj_begin(jw *w) { begin(w, "{"); }
void jw_obj_end(jw *w) { end(w, "}"); }
void jw_arr_begin(jw *w) { begin(w, "["); }
void jw_arr_end(jw *w) { end(w, "]"); }

void jw_key(jw *w, const char *key)
{
    value_prefix(w);
    w->after_key = 1; /* the key string itself takes no comma */
    jw_str(w, key);
    puts_(w, ":");
    w->after_key = 1; /* nor does its value */
}

void jw_real(jw *w, kc_real x)
{
    char num[40];
    value_prefix(w);
    if (!kc_isfinite(x)) {
        puts_(w, "null");
        return;
    }
    snprintf(num, sizeof num, REAL_FMT, (double)x);
    puts_(w, num);
}

void jw_bool(jw *w, int b)
{
    value_prefix(w);
    puts_(w, b ? "true" : "false");
}

void jw_null(jw *w)
{
    value_prefix(w);
    puts_(w, "null");
}

void jw_raw(jw *w, const char *json)
{
    value_prefix(w);
    puts_(w, json);
}

void jw_str(jw *w, const char *s)
{
    value_prefix(w);
    puts_(w, "\"");
    for (const unsigned char *p = (const unsigned char *)s; *p != '\0'; p++) {
        char esc[8];
        if (*p == '"' || *p == '\\') {
            esc[0] = '\\';
            esc[1] = (char)*p;
            put(w, esc, 2);
        } else if (*p < 0x20) {
            snprintf(esc, sizeof esc, "\\u%04x", (unsigned)*p);
            puts_(w, esc);
        } else {
            put(w, (const char *)p, 1);
        }
    }
    puts_(w, "\"");
}

void jw_reals(jw *w, const kc_real *x, int n)
{
    jw_arr_begin(w);
    for (int i = 0; i < n; i++)
        jw_real(w, x[i]);
    jw_arr_end(w);
}

void jw_mat3(jw *w, const kc_mat3 *m)
{
    jw_arr_begin(w);
    for (int i = 0; i < 3; i++)
        jw_reals(w, m->m[i], 3);
    jw_arr_end(w);
}

void jw_mat4(jw *w, const kc_mat4 *m)
{
    jw_arr_begin(w);
    for (int i = 0; i < 4; i++)
        jw_reals(w, m->m[i], 4);
    jw_arr_end(w);
}

void jw_pose(jw *w, const kc_pose *p)
{
    kc_mat4 m;
    kc_pose_to_mat4(p, &m);
    jw_mat4(w, &m);
}
