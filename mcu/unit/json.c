/* SPDX-License-Identifier: BSD-3-Clause */
/* json.c - a recursive-descent JSON reader behind the jansson subset of
 * jansson.h. The document is read into one buffer and parsed in place:
 * strings are unescaped where they stand (never longer than their source)
 * and terminated there. Values live in blocks of nodes chained from the
 * root; a container's children are collected on a shared stack and copied
 * into the container's own array once it closes. Nesting is bounded. */
#include "jansson.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_DEPTH 64
#define BLOCK_NODES 4096

struct json_t {
    json_type type;
    size_t n; /* children of an object or array */
    union {
        double num;
        const char *str;
        json_t **items;
    } u;
    const char **keys; /* object keys, in the order of u.items */
};

/* One allocation; freed by json_decref(root). */
typedef struct alloc {
    struct alloc *next;
} alloc;

typedef struct parser {
    char *p, *end;
    int line;
    json_error_t *err;
    alloc *allocs;          /* every allocation, newest first */
    json_t *block;          /* the current node block */
    size_t block_used;
    json_t **stack;         /* children of the open containers */
    const char **key_stack; /* their keys (objects) */
    size_t sp, cap;
} parser;

/* The root owns its buffer and allocations through a header before it. */
typedef struct root {
    alloc *allocs;
    char *text;
    json_t node;
} root;

static void *take(parser *ps, size_t size)
{
    alloc *a = malloc(sizeof(alloc) + size);
    if (a == NULL)
        return NULL;
    a->next = ps->allocs;
    ps->allocs = a;
    return a + 1;
}

static int error(parser *ps, const char *what)
{
    if (ps->err != NULL) {
        ps->err->line = ps->line;
        snprintf(ps->err->text, sizeof ps->err->text, "%s", what);
    }
    return -1;
}

static json_t *node(parser *ps, json_type type)
{
    if (ps->block == NULL || ps->block_used == BLOCK_NODES) {
        ps->block = take(ps, sizeof(json_t) * BLOCK_NODES);
        ps->block_used = 0;
        if (ps->block == NULL)
            return NULL;
    }
    json_t *j = &ps->block[ps->block_used++];
    memset(j, 0, sizeof *j);
    j->type = type;
    return j;
}

static void skip_space(parser *ps)
{
    while (ps->p < ps->end && (*ps->p == ' ' || *ps->p == '\t' || *ps->p == '\n' || *ps->p == '\r')) {
        if (*ps->p == '\n')
            ps->line++;
        ps->p++;
    }
}

static int push(parser *ps, json_t *child, const char *key)
{
    if (ps->sp == ps->cap) {
        size_t cap = ps->cap ? 2 * ps->cap : 1024;
        json_t **s = realloc(ps->stack, cap * sizeof *s);
        if (s == NULL)
            return error(ps, "out of memory");
        ps->stack = s;
        const char **k = realloc(ps->key_stack, cap * sizeof *k);
        if (k == NULL)
            return error(ps, "out of memory");
        ps->key_stack = k;
        ps->cap = cap;
    }
    ps->stack[ps->sp] = child;
    ps->key_stack[ps->sp] = key;
    ps->sp++;
    return 0;
}

static unsigned hex4(const char *s)
{
    unsigned v = 0;
    for (int i = 0; i < 4; i++) {
        char c = s[i];
        unsigned d = (c >= '0' && c <= '9') ? (unsigned)(c - '0')
                     : (c >= 'a' && c <= 'f') ? (unsigned)(c - 'a' + 10)
                     : (c >= 'A' && c <= 'F') ? (unsigned)(c - 'A' + 10) : 16u;
        if (d == 16u)
            return 0x110000u;
        v = v * 16u + d;
    }
    return v;
}

static char *put_utf8(char *o, unsigned cp)
{
    if (cp < 0x80u) {
        *o++ = (char)cp;
    } else if (cp < 0x800u) {
        *o++ = (char)(0xC0u | (cp >> 6));
        *o++ = (char)(0x80u | (cp & 0x3Fu));
    } else if (cp < 0x10000u) {
        *o++ = (char)(0xE0u | (cp >> 12));
        *o++ = (char)(0x80u | ((cp >> 6) & 0x3Fu));
        *o++ = (char)(0x80u | (cp & 0x3Fu));
    } else {
        *o++ = (char)(0xF0u | (cp >> 18));
        *o++ = (char)(0x80u | ((cp >> 12) & 0x3Fu));
        *o++ = (char)(0x80u | ((cp >> 6) & 0x3Fu));
        *o++ = (char)(0x80u | (cp & 0x3Fu));
    }
    return o;
}

/* At the opening quote: unescapes in place, returns the string or NULL. */
static const char *string(parser *ps)
{
    char *start = ++ps->p, *o = start;
    while (ps->p < ps->end && *ps->p != '"') {
        char c = *ps->p++;
        if (c != '\\') {
            *o++ = c;
            continue;
        }
        if (ps->p >= ps->end)
            break;
        c = *ps->p++;
        switch (c) {
        case 'n': *o++ = '\n'; break;
        case 't': *o++ = '\t'; break;
        case 'r': *o++ = '\r'; break;
        case 'b': *o++ = '\b'; break;
        case 'f': *o++ = '\f'; break;
        case 'u': {
            if (ps->end - ps->p < 4)
                return NULL;
            unsigned cp = hex4(ps->p);
            ps->p += 4;
            if (cp >= 0xD800u && cp < 0xDC00u && ps->end - ps->p >= 6 && ps->p[0] == '\\' && ps->p[1] == 'u') {
                unsigned lo = hex4(ps->p + 2);
                if (lo >= 0xDC00u && lo < 0xE000u) {
                    cp = 0x10000u + ((cp - 0xD800u) << 10) + (lo - 0xDC00u);
                    ps->p += 6;
                }
            }
            if (cp > 0x10FFFFu)
                return NULL;
            o = put_utf8(o, cp);
            break;
        }
        default: *o++ = c; break; /* \" \\ \/ */
        }
    }
    if (ps->p >= ps->end)
        return NULL;
    ps->p++; /* the closing quote */
    *o = '\0';
    return start;
}

static json_t *value(parser *ps, int depth);

/* A container from its opening bracket; object when obj. */
static json_t *container(parser *ps, int depth, int obj)
{
    json_t *j = node(ps, obj ? JSON_OBJECT : JSON_ARRAY);
    if (j == NULL || depth >= MAX_DEPTH) {
        error(ps, depth >= MAX_DEPTH ? "nested too deeply" : "out of memory");
        return NULL;
    }
    char close = obj ? '}' : ']';
    size_t base = ps->sp;
    ps->p++;
    skip_space(ps);
    if (ps->p < ps->end && *ps->p == close) {
        ps->p++;
        return j;
    }
    for (;;) {
        const char *key = NULL;
        skip_space(ps);
        if (obj) {
            if (ps->p >= ps->end || *ps->p != '"' || (key = string(ps)) == NULL) {
                error(ps, "expected a key");
                return NULL;
            }
            skip_space(ps);
            if (ps->p >= ps->end || *ps->p != ':') {
                error(ps, "expected ':'");
                return NULL;
            }
            ps->p++;
        }
        json_t *child = value(ps, depth + 1);
        if (child == NULL || push(ps, child, key) != 0)
            return NULL;
        skip_space(ps);
        if (ps->p < ps->end && *ps->p == ',') {
            ps->p++;
            continue;
        }
        if (ps->p < ps->end && *ps->p == close) {
            ps->p++;
            break;
        }
        error(ps, obj ? "expected ',' or '}'" : "expected ',' or ']'");
        return NULL;
    }
    j->n = ps->sp - base;
    j->u.items = take(ps, j->n * sizeof(json_t *));
    if (j->u.items == NULL) {
        error(ps, "out of memory");
        return NULL;
    }
    memcpy(j->u.items, ps->stack + base, j->n * sizeof(json_t *));
    if (obj) {
        j->keys = take(ps, j->n * sizeof(const char *));
        if (j->keys == NULL) {
            error(ps, "out of memory");
            return NULL;
        }
        memcpy(j->keys, ps->key_stack + base, j->n * sizeof(const char *));
    }
    ps->sp = base;
    return j;
}

static int literal(parser *ps, const char *word)
{
    size_t n = strlen(word);
    if ((size_t)(ps->end - ps->p) < n || memcmp(ps->p, word, n) != 0)
        return 0;
    ps->p += n;
    return 1;
}

static json_t *value(parser *ps, int depth)
{
    skip_space(ps);
    if (ps->p >= ps->end) {
        error(ps, "unexpected end of input");
        return NULL;
    }
    char c = *ps->p;
    if (c == '{' || c == '[')
        return container(ps, depth, c == '{');
    json_t *j;
    if (c == '"') {
        const char *s = string(ps);
        if (s == NULL) {
            error(ps, "bad string");
            return NULL;
        }
        j = node(ps, JSON_STRING);
        if (j != NULL)
            j->u.str = s;
    } else if (literal(ps, "true")) {
        j = node(ps, JSON_TRUE);
    } else if (literal(ps, "false")) {
        j = node(ps, JSON_FALSE);
    } else if (literal(ps, "null")) {
        j = node(ps, JSON_NULL);
    } else {
        char *after;
        double v = strtod(ps->p, &after);
        if (after == ps->p) {
            error(ps, "unexpected character");
            return NULL;
        }
        int integer = 1;
        for (const char *q = ps->p; q < after; q++)
            if (*q == '.' || *q == 'e' || *q == 'E')
                integer = 0;
        ps->p = after;
        j = node(ps, integer ? JSON_INTEGER : JSON_REAL);
        if (j != NULL)
            j->u.num = v;
    }
    if (j == NULL)
        error(ps, "out of memory");
    return j;
}

static void free_allocs(alloc *a)
{
    while (a != NULL) {
        alloc *next = a->next;
        free(a);
        a = next;
    }
}

json_t *json_load_file(const char *path, size_t flags, json_error_t *err)
{
    (void)flags;
    parser ps;
    memset(&ps, 0, sizeof ps);
    ps.err = err;
    ps.line = 1;
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        error(&ps, "cannot open the file");
        return NULL;
    }
    long size = -1;
    if (fseek(f, 0, SEEK_END) == 0)
        size = ftell(f);
    root *r = NULL;
    char *text = size >= 0 ? malloc((size_t)size + 1) : NULL;
    if (text != NULL && fseek(f, 0, SEEK_SET) == 0 && fread(text, 1, (size_t)size, f) == (size_t)size) {
        text[size] = '\0';
        ps.p = text;
        ps.end = text + size;
        json_t *j = value(&ps, 0);
        skip_space(&ps);
        if (j != NULL && ps.p != ps.end) {
            error(&ps, "text after the document");
            j = NULL;
        }
        if (j != NULL && (r = malloc(sizeof *r)) != NULL) {
            r->allocs = ps.allocs;
            r->text = text;
            r->node = *j;
        } else if (j != NULL) {
            error(&ps, "out of memory");
        }
    } else {
        error(&ps, "cannot read the file");
    }
    fclose(f);
    free(ps.stack);
    free(ps.key_stack);
    if (r == NULL) {
        free_allocs(ps.allocs);
        free(text);
        return NULL;
    }
    return &r->node;
}

void json_decref(json_t *json)
{
    if (json == NULL)
        return;
    root *r = (root *)(void *)((char *)json - offsetof(root, node));
    free_allocs(r->allocs);
    free(r->text);
    free(r);
}

json_type json_typeof(const json_t *json) { return json->type; }

size_t json_array_size(const json_t *array) { return json_is_array(array) ? array->n : 0; }

json_t *json_array_get(const json_t *array, size_t index)
{
    return json_is_array(array) && index < array->n ? array->u.items[index] : NULL;
}

json_t *json_object_get(const json_t *object, const char *key)
{
    if (!json_is_object(object))
        return NULL;
    for (size_t i = 0; i < object->n; i++)
        if (strcmp(object->keys[i], key) == 0)
            return object->u.items[i];
    return NULL;
}

const char *json_string_value(const json_t *string) { return json_is_string(string) ? string->u.str : NULL; }

double json_number_value(const json_t *json)
{
    return json_is_number(json) ? json->u.num : 0.0;
}
