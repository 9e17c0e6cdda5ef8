/* SPDX-License-Identifier: BSD-3-Clause */
/*
 * jansson.h - the part of jansson's API that kinctl's unit tests use to read
 * the reference vectors, for bare metal (jansson is not built for it). On
 * the board the files are read from the host through semihosting.
 *
 * json_load_file reads the whole document into one tree; every value found
 * in it is borrowed from the root and lives until json_decref(root), which
 * frees the tree (only roots are reference-counted here). Strings are
 * UTF-8 with \uXXXX escapes decoded (surrogate pairs joined); numbers
 * convert with strtod, so they round exactly as jansson's do.
 */
#ifndef KINCTL_MCU_JANSSON_H
#define KINCTL_MCU_JANSSON_H

#include <stddef.h>

typedef enum json_type {
    JSON_OBJECT,
    JSON_ARRAY,
    JSON_STRING,
    JSON_INTEGER,
    JSON_REAL,
    JSON_TRUE,
    JSON_FALSE,
    JSON_NULL
} json_type;

typedef struct json_t json_t;

#define JSON_ERROR_TEXT_LENGTH 160
typedef struct json_error_t {
    int line;
    char text[JSON_ERROR_TEXT_LENGTH];
} json_error_t;

json_t *json_load_file(const char *path, size_t flags, json_error_t *error);
void json_decref(json_t *json);

json_type json_typeof(const json_t *json);
#define json_is_object(j) ((j) != NULL && json_typeof(j) == JSON_OBJECT)
#define json_is_array(j) ((j) != NULL && json_typeof(j) == JSON_ARRAY)
#define json_is_string(j) ((j) != NULL && json_typeof(j) == JSON_STRING)
#define json_is_integer(j) ((j) != NULL && json_typeof(j) == JSON_INTEGER)
#define json_is_real(j) ((j) != NULL && json_typeof(j) == JSON_REAL)
#define json_is_number(j) (json_is_integer(j) || json_is_real(j))
#define json_is_true(j) ((j) != NULL && json_typeof(j) == JSON_TRUE)
#define json_is_false(j) ((j) != NULL && json_typeof(j) == JSON_FALSE)
#define json_is_null(j) ((j) != NULL && json_typeof(j) == JSON_NULL)

/* NULL or 0 for a value of another type, as jansson. */
size_t json_array_size(const json_t *array);
json_t *json_array_get(const json_t *array, size_t index);
json_t *json_object_get(const json_t *object, const char *key);
const char *json_string_value(const json_t *string);
double json_number_value(const json_t *json);

#endif /* KINCTL_MCU_JANSSON_H */
